"""Immutable results of the analyses, in the JSON shapes of shared/spec/interface.md."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np


@dataclass(frozen=True)
class Mode:
    f_hz: float
    label: str                              # flap1, chord1, torsion1, axial1, ...
    participation: dict[str, float] = field(default_factory=dict)  # share of tip motion by kind
    damping_ratio: float | None = None      # from the gyroscopic problem, if known


@dataclass(frozen=True)
class ModalResult:
    model: str
    rpm: float
    dofs: int
    elapsed_s: float
    coriolis: bool
    modes: tuple[Mode, ...]
    shapes: Any = None                      # (n, k) mode shapes, when kept

    def frequencies(self) -> np.ndarray:
        return np.array([m.f_hz for m in self.modes])

    def by_label(self) -> dict[str, float]:
        return {m.label: m.f_hz for m in self.modes}

    def to_json(self) -> dict[str, Any]:
        return {
            "model": self.model, "rpm": self.rpm, "dofs": self.dofs,
            "elapsed_s": round(self.elapsed_s, 6), "coriolis": self.coriolis,
            "modes": [{"f_hz": m.f_hz, "label": m.label,
                       **({"participation": m.participation} if m.participation else {})}
                      for m in self.modes],
        }
