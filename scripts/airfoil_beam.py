"""The measurements of docs/extended-beam.md, "Any blade", on the spec's NACA blade (extended beam):

    PYTHONPATH=. OMP_NUM_THREADS=1 python scripts/airfoil_beam.py stations   # stations along the span
    PYTHONPATH=. OMP_NUM_THREADS=1 python scripts/airfoil_beam.py terms      # the couplings dropped
    PYTHONPATH=. OMP_NUM_THREADS=1 python scripts/airfoil_beam.py basis      # N against N = 16
    PYTHONPATH=. OMP_NUM_THREADS=1 python scripts/airfoil_beam.py modes      # bending energy per mode

Frequency changes in per cent of the first five modes at 0 and 10000 r/min (Coriolis on).
"""

from __future__ import annotations

import dataclasses
import math
import sys

import numpy as np

from reduced_model.airfoil import span_sections
from reduced_model.basis import sample
from reduced_model.beam import assemble, tip_body
from reduced_model.modal import modes_at
from reduced_model.models import EXTENDED
from shroud.core.modes import label_modes
from shroud.params import Parameters

BLADE = ["blade.section=naca4", "blade.chord_taper=0.75", "blade.thickness_taper=0.6", "contact.alpha_deg=15"]
SPEEDS = (0.0, 10000.0)
PARAMS = Parameters().with_overrides(BLADE).updated(EXTENDED)


def beam(count: int = 4, offset: bool = True, helix: bool = True, N: int | None = None):
    p = PARAMS

    def sections(x):
        s = span_sections(p.blade, x, nu=p.material.nu, count=count)
        if not offset:
            s = dataclasses.replace(s, shear_v=0 * s.shear_v, shear_w=0 * s.shear_w)
        if not helix:
            s = dataclasses.replace(s, I_rrv=0 * s.I_rrv, I_rrw=0 * s.I_rrw)
        return s

    return assemble(p.blade, p.material, tip_body(p), N or p.reduced.N, True, sections)


def frequencies(matrices) -> list[np.ndarray]:
    return [np.array(modes_at(matrices, 2 * math.pi * rpm / 60, 5, True).f_hz) for rpm in SPEEDS]


def change(matrices, reference) -> str:
    return " | ".join(" ".join(f"{100 * (f / r - 1):+.4f}" for f, r in zip(fs, rs))
                      for fs, rs in zip(frequencies(matrices), reference))


def main(what: str) -> None:
    if what == "stations":
        reference = frequencies(beam(count=12))
        for count in (1, 2, 3, 4, 6, 8):
            print(f"{count:2d} stations: {change(beam(count=count), reference)}")
    elif what == "terms":
        reference = frequencies(beam())
        for name, kwargs in (("shear centre", dict(offset=False)), ("helix", dict(helix=False)),
                             ("both", dict(offset=False, helix=False))):
            print(f"without {name:12s}: {change(beam(**kwargs), reference)}")
    elif what == "basis":
        reference = frequencies(beam(N=16))
        for N in (6, 8, 10, 12):
            print(f"N = {N:2d}: {change(beam(N=N), reference)}")
    elif what == "modes":
        matrices, N, p = beam(), PARAMS.reduced.N, PARAMS
        q = sample(N, p.blade.length, points=200)
        beta = p.blade.beta(q.x)
        for rpm in SPEEDS:
            modes = modes_at(matrices, 2 * math.pi * rpm / 60, 5, True)
            labels, _ = label_modes(matrices.tip_kinematics(modes.shapes))
            for f, label, shape in zip(modes.f_hz, labels, modes.shapes.T):
                shape = np.real(shape * np.exp(-1j * np.angle(shape[np.argmax(np.abs(shape))])))
                v_Y, w_Z = q.value @ shape[N:2 * N], q.value @ shape[2 * N:3 * N]
                flap = np.cos(beta) * v_Y + np.sin(beta) * w_Z            # section frame
                chord = -np.sin(beta) * v_Y + np.cos(beta) * w_Z
                energy = [float(np.sum(q.weight * a**2)) for a in (flap, chord)]
                print(f"{rpm:7.0f} r/min {f:9.2f} Hz {label:9s} flap share of the bending "
                      f"{energy[0] / sum(energy):.2f}")
    else:
        raise SystemExit(f"unknown measurement {what!r}; one of stations, terms, basis, modes")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "terms")
