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


@dataclass(frozen=True)
class HBResult:
    """A steady-state branch over speed by harmonic balance, points in continuation order.

    rpm may go back at a fold; ``stable`` from the Floquet multipliers;
    amplitudes are (max - min)/2 over one period, m. ``bifurcations``: where
    stability changes ({"rpm", "amplitude", "kind"}: fold, period-doubling,
    Neimark-Sacker). ``spectral_tail``: the share (RMS) of the contact
    forces' spectrum above H at the point of the largest contact forces
    (grazing points, whose brief touches are all tail, would say nothing).
    """

    model: str
    harmonics: int
    samples: int
    rpm: np.ndarray
    amplitude_v_L: np.ndarray
    amplitude_w_L: np.ndarray
    stable: np.ndarray
    max_multiplier: np.ndarray
    bifurcations: tuple[dict, ...]
    spectral_tail: float
    iterations: int
    complete: bool
    stopped: str | None
    dofs: int
    condensed: bool
    elapsed_s: float
    X: np.ndarray | None = None        # (points, nh nx) harmonic coefficients of the unknowns, per point
    harmonics_tried: tuple[dict, ...] = ()   # {"harmonics", "spectral_tail"} when H was chosen to a tail

    @classmethod
    def from_points(cls, model, harmonics, samples, rpm, details, iterations, complete, stopped, dofs,
                    condensed, elapsed_s, X=None) -> "HBResult":
        from shroud.core.floquet import bifurcation
        amp = np.array([d["amplitude_v_L"] for d in details])
        bif = []
        for i in range(1, len(details)):
            kind = bifurcation(details[i - 1]["multipliers"], details[i]["multipliers"])
            if kind:
                bif.append({"rpm": 0.5 * (rpm[i - 1] + rpm[i]), "amplitude": 0.5 * (amp[i - 1] + amp[i]),
                            "kind": kind})
        return cls(model=model, harmonics=harmonics, samples=samples, rpm=np.asarray(rpm, float),
                   amplitude_v_L=amp, amplitude_w_L=np.array([d["amplitude_w_L"] for d in details]),
                   stable=np.array([d["stable"] for d in details], bool),
                   max_multiplier=np.array([float(np.abs(d["multipliers"]).max(initial=0.0)) for d in details]),
                   bifurcations=tuple(bif),
                   spectral_tail=max(details, key=lambda d: d["force_rms"])["tail"] if details else 0.0,
                   iterations=int(sum(iterations)), complete=complete, stopped=stopped, dofs=dofs,
                   condensed=condensed, elapsed_s=elapsed_s, X=None if X is None else np.array(X))

    @property
    def resonance(self) -> dict[str, float]:
        """Speed and amplitude of the largest v_L amplitude on the branch."""
        if self.amplitude_v_L.size == 0:
            return {"rpm": float("nan"), "amplitude": float("nan")}
        i = int(np.argmax(self.amplitude_v_L))
        return {"rpm": float(self.rpm[i]), "amplitude": float(self.amplitude_v_L[i])}

    def to_json(self) -> dict[str, Any]:
        return {"model": self.model, "method": "hb", "harmonics": self.harmonics, "samples": self.samples,
                "rpm": [float(r) for r in self.rpm], "amplitude_v_L": [float(a) for a in self.amplitude_v_L],
                "amplitude_w_L": [float(a) for a in self.amplitude_w_L],
                "stable": [bool(s) for s in self.stable],
                "max_multiplier": [float(m) for m in self.max_multiplier],
                "bifurcations": list(self.bifurcations), "resonance": self.resonance,
                "spectral_tail": self.spectral_tail, "harmonics_tried": list(self.harmonics_tried),
                "complete": self.complete, "stopped": self.stopped,
                "dofs": self.dofs, "condensed": self.condensed, "newton_iterations": self.iterations,
                "elapsed_s": round(self.elapsed_s, 6)}

    def to_csv(self, path) -> None:
        """One row per branch point: rpm, amplitudes (m), stable (0/1), largest |multiplier|."""
        data = np.column_stack([self.rpm, self.amplitude_v_L, self.amplitude_w_L, self.stable,
                                self.max_multiplier])
        np.savetxt(path, data, delimiter=",", fmt=["%.6f", "%.9e", "%.9e", "%d", "%.6f"],
                   header=f"model {self.model}, harmonic balance H = {self.harmonics}\n"
                          "rpm,amplitude_v_L_m,amplitude_w_L_m,stable,max_multiplier")

    def plot(self, ax=None, label: str | None = None, colour=None, scale: float = 1e3, **line):
        """v_L amplitude (mm) over speed: stable stretches solid, unstable dashed; bifurcations marked.

        ``line``: further matplotlib line properties (e.g. linewidth).
        """
        if ax is None:
            from shroud.core.plotting import figure
            _, axes = figure(1, 1)
            ax = axes[0][0]
        drawn = None
        start = 0
        for i in range(1, len(self.rpm) + 1):
            if i == len(self.rpm) or self.stable[i] != self.stable[start]:
                sl = slice(start, min(i + 1, len(self.rpm)))
                drawn, = ax.plot(self.rpm[sl], self.amplitude_v_L[sl] * scale,
                                "-" if self.stable[start] else "--",
                                color=colour if colour is not None else (drawn.get_color() if drawn else None),
                                label=label if start == 0 else None, **line)
                start = i
        marks = {"fold": "o", "period-doubling": "s", "Neimark-Sacker": "^"}
        for b in self.bifurcations:
            ax.plot(b["rpm"], b["amplitude"] * scale, marks[b["kind"]], color="k", ms=4, mfc="none")
        ax.set_xlabel("speed (r/min)")
        ax.set_ylabel("amplitude of v_L (mm)")
        return ax
