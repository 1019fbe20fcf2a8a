"""Immutable results of the analyses, in one place, as ROSS keeps them.

Each result serializes itself (``to_json`` in the JSON shapes of the
interface contract, ``to_csv``) and draws itself (``plot(ax=None)`` returns
the matplotlib axes it drew on, creating a figure when none is given), so a
study is compute -> plot -> report.

* :class:`ModalResult`: natural frequencies at one speed, labelled by tip
  kinematics (flap, chord, torsion, axial);
* :class:`TransientResult`: one Newmark run and its steady-state measures;
* :class:`SweepResult`: steady-state tip amplitude over speed (:class:`RingSweepResult`: a ring's, every
  blade's);
* :class:`CampbellResult`: frequencies tracked over speed;
* :class:`HBResult`: a steady-state branch over speed by harmonic balance,
  with the stability of every point.

Units: SI (m, N, s, Hz); speeds in r/min.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from shroud.base.outputs import open_replacing, replacing
from shroud.core import signals
from shroud.core.plotting import MODEL_COLOURS, figure

if TYPE_CHECKING:       # the integrator (numba) loads only with a transient result
    from shroud.core.newmark import EnergyBalance, Trajectory


def _axes(ax, width: float = 6.4, height: float = 3.2):
    """``ax`` itself, or the axes of a new one-panel figure."""
    return ax if ax is not None else figure(width=width, height=height)[1][0, 0]


def _finite_or_none(values) -> list[float | None]:
    return [None if not np.isfinite(x) else float(x) for x in values]


def _write_rows(path: Path, header: list[str], rows, comment: str | None = None) -> Path:
    path = Path(path)
    with open_replacing(path) as fh:
        if comment:
            fh.write(f"# {comment}\n")
        writer = csv.writer(fh)
        writer.writerow(header)
        writer.writerows(rows)
    return path


# ----------------------------------------------------------------------------- modal

@dataclass(frozen=True)
class Mode:
    f_hz: float
    label: str                              # flap1, chord1, torsion1, axial1, ...
    participation: dict[str, float] = field(default_factory=dict)  # share of tip motion by kind
    damping_ratio: float | None = None      # from the gyroscopic problem, if known


@dataclass(frozen=True)
class ModalResult:
    """Natural frequencies of one model at one speed."""

    model: str
    rpm: float
    dofs: int
    elapsed_s: float
    coriolis: bool
    modes: tuple[Mode, ...]
    shapes: Any = None                      # (n, k) mode shapes, when kept

    def frequencies(self) -> np.ndarray:
        """Frequencies in the order of the modes, Hz.

        >>> ModalResult("m", 0.0, 2, 0.0, False, (Mode(10.0, "flap1"), Mode(30.0, "chord1"))).frequencies()
        array([10., 30.])
        """
        return np.array([m.f_hz for m in self.modes])

    def by_label(self) -> dict[str, float]:
        return {m.label: m.f_hz for m in self.modes}

    def to_json(self) -> dict[str, Any]:
        return {
            "model": self.model, "rpm": self.rpm, "dofs": self.dofs,
            "elapsed_s": round(self.elapsed_s, 6), "coriolis": self.coriolis,
            "modes": [{"f_hz": m.f_hz, "label": m.label,
                       **({"participation": m.participation} if m.participation else {}),
                       **({"damping_ratio": m.damping_ratio} if m.damping_ratio is not None else {})}
                      for m in self.modes],
        }

    def to_csv(self, path: Path) -> Path:
        """One row per mode: label, frequency (Hz), damping ratio (-, empty if unknown)."""
        rows = [(m.label, f"{m.f_hz:.6f}", "" if m.damping_ratio is None else f"{m.damping_ratio:.6g}")
                for m in self.modes]
        return _write_rows(path, ["label", "f_hz", "damping_ratio"], rows,
                           f"{self.model} at {self.rpm:g} r/min, {self.dofs} DOF")

    def plot(self, ax=None, offset: float = 0.0, width: float = 0.8, **bar):
        """Frequencies as bars over the mode labels (log scale), coloured by model."""
        ax = _axes(ax)
        x = np.arange(len(self.modes)) + offset
        ax.bar(x, self.frequencies(), width=width, label=f"{self.model} ({self.dofs} DOF)",
               color=bar.pop("color", MODEL_COLOURS.get(self.model)), **bar)
        ax.set_xticks(np.arange(len(self.modes)), [m.label for m in self.modes])
        ax.set_yscale("log")
        ax.set_ylabel("frequency (Hz)")
        ax.set_title(f"{self.model}: modes at {self.rpm:g} r/min")
        return ax


# ----------------------------------------------------------------------------- transient

CSV_COLUMNS = ("t", "v_L", "w_L", "w_s1", "w_s2", "N1", "N2", "Ff1", "Ff2", "state1", "state2")
CSV_UNITS = "s, m, m, m, m, N, N, N, N, 0 separate / 1 stick / 2 slip"


@dataclass(frozen=True)
class StaticResult:
    """The static response to a force at the blade tip, on top of the centrifugal state at ``rpm``.

    ``tip``: the tip-centre displacement caused by the force, m: global X, Y,
    Z and v_L, w_L along e_v(L), e_w(L); X is None for a model that has no
    radial motion at its tip.
    """

    model: str
    rpm: float
    dofs: int
    force: tuple[float, float, float]    # N, global X, Y, Z
    tip: dict[str, float | None]
    elapsed_s: float

    def to_json(self) -> dict[str, Any]:
        return {"model": self.model, "rpm": self.rpm, "dofs": self.dofs, "force": list(self.force),
                "tip": dict(self.tip), "elapsed_s": self.elapsed_s}


def tip_displacement(xyz, beta_tip: float) -> dict[str, float | None]:
    """``{"X", "Y", "Z", "v_L", "w_L"}`` of a tip displacement (X may be None), m (geometry.md frames)."""
    X, Y, Z = xyz
    c, s = math.cos(beta_tip), math.sin(beta_tip)
    return {"X": None if X is None else float(X), "Y": float(Y), "Z": float(Z),
            "v_L": float(c * Y + s * Z), "w_L": float(-s * Y + c * Z)}


def steady_state(trajectory: Trajectory, steps_per_period: int) -> dict[str, Any]:
    """Amplitudes, peaks, state fractions and period of a finished trajectory."""
    tr, spp = trajectory, steps_per_period
    return {
        "amplitude": {"v_L": signals.amplitude(tr.tip[:, 0], spp),
                      "w_L": signals.amplitude(tr.tip[:, 1], spp)},
        "peak": {"N1": signals.peak(tr.normal[:, 0], spp), "N2": signals.peak(tr.normal[:, 1], spp),
                 "Ff1": signals.peak(tr.friction[:, 0], spp), "Ff2": signals.peak(tr.friction[:, 1], spp)},
        "state_fraction": {f"side{s + 1}": signals.state_fractions(tr.state[:, s], spp) for s in range(2)},
        "period": signals.detect_period(tr.tip[:, 0], spp),
    }


def write_trajectory_csv(path: Path, tr: Trajectory, status: str) -> Path:
    """The time series, one row per step; the header's first line gives the run's status."""
    data = np.column_stack([tr.t, tr.tip, tr.tangential, tr.normal, tr.friction, tr.state])
    fmt = ["%.9e"] * 9 + ["%d", "%d"]
    header = f"status: {status}\nunits: {CSV_UNITS}\n" + ",".join(CSV_COLUMNS)
    with replacing(Path(path)) as tmp:
        np.savetxt(tmp, data, delimiter=",", fmt=fmt, header=header)
    return Path(path)


@dataclass(frozen=True)
class TransientResult:
    """One transient run (paper Sect. 2.1) and what the paper reads off it."""

    model: str
    rpm: float
    dofs: int
    steps: int
    steps_per_period: int
    elapsed_s: float
    amplitude: dict[str, float]          # v_L, w_L: (max - min)/2 over the last 10 periods, m
    peak: dict[str, float]               # N1, N2, Ff1, Ff2: largest |.| over the last 10 periods, N
    state_fraction: dict[str, dict[str, float]]
    period: int | None                   # in excitation periods (1 = P1), None if none up to P10
    energy: EnergyBalance | None
    contact_treatment: str
    timeseries: str | None
    trajectory: Trajectory

    @classmethod
    def from_trajectory(cls, trajectory: Trajectory, *, model: str, rpm: float, dofs: int,
                        steps_per_period: int, contact_treatment: str,
                        timeseries: str | None = None) -> "TransientResult":
        """The result of a finished run, its steady-state measures taken over the last periods."""
        return cls(model=model, rpm=rpm, dofs=dofs, steps=trajectory.steps,
                   steps_per_period=steps_per_period, elapsed_s=trajectory.elapsed_s,
                   energy=trajectory.energy, contact_treatment=contact_treatment,
                   timeseries=timeseries, trajectory=trajectory,
                   **steady_state(trajectory, steps_per_period))

    def to_json(self) -> dict[str, Any]:
        return {
            "model": self.model, "rpm": self.rpm, "dofs": self.dofs, "steps": self.steps,
            "elapsed_s": round(self.elapsed_s, 6), "amplitude": self.amplitude, "peak": self.peak,
            "state_fraction": self.state_fraction, "period": self.period,
            "timeseries": self.timeseries, "contact_treatment": self.contact_treatment,
            "energy_balance": self.energy.to_json() if self.energy else None,
        }

    def to_csv(self, path: Path, status: str = "complete") -> Path:
        """The time series (columns CSV_COLUMNS, units CSV_UNITS)."""
        return write_trajectory_csv(path, self.trajectory, status)

    def plot(self, ax=None, signal: str = "v_L", periods: int = signals.STEADY_PERIODS, **line):
        """One recorded signal (v_L, w_L in um; N1, N2, Ff1, Ff2 in N) over the last ``periods``."""
        columns = {"v_L": (self.trajectory.tip, 0, 1e6, "um"), "w_L": (self.trajectory.tip, 1, 1e6, "um"),
                   "N1": (self.trajectory.normal, 0, 1.0, "N"), "N2": (self.trajectory.normal, 1, 1.0, "N"),
                   "Ff1": (self.trajectory.friction, 0, 1.0, "N"), "Ff2": (self.trajectory.friction, 1, 1.0, "N")}
        data, col, scale, unit = columns[signal]
        ax = _axes(ax)
        t = signals.last_periods(self.trajectory.t, self.steps_per_period, periods)
        x = signals.last_periods(data[:, col], self.steps_per_period, periods)
        period_s = self.steps_per_period * self.trajectory.dt
        ax.plot(t / period_s, scale * x, label=line.pop("label", f"{self.model} ({self.dofs} DOF)"),
                color=line.pop("color", MODEL_COLOURS.get(self.model)), **line)
        ax.set_xlabel("time (excitation periods)")
        ax.set_ylabel(f"{signal} ({unit})")
        return ax


# ----------------------------------------------------------------------------- sweep

@dataclass(frozen=True)
class SweepResult:
    """Steady-state tip amplitude over speed (paper Figs. 4, 7, 11-17)."""

    model: str
    rpm: np.ndarray
    amplitude_v_L: np.ndarray         # m; NaN where the run diverged
    amplitude_w_L: np.ndarray         # m
    period: tuple[int | None, ...]    # detected period per speed (1 = P1)
    slip_fraction: np.ndarray         # mean share of the last periods spent slipping (both sides)
    dofs: int
    elapsed_s: float                  # wall time of the sweep
    cpu_s: float                      # summed time of the runs (build + integration)
    # False where the run had not settled by the period cap (or diverged): such an
    # amplitude is a transient's, never a steady state (shroud.analysis.sweep.Settling).
    settled: tuple[bool, ...] = ()

    @property
    def resonance(self) -> dict[str, float]:
        """Speed and amplitude of the largest v_L amplitude (every point; the studies read
        the resonance off settled points, shroud.analysis.sweep.steady_resonance)."""
        if not np.any(np.isfinite(self.amplitude_v_L)):
            return {"rpm": math.nan, "amplitude": math.nan}
        i = int(np.nanargmax(self.amplitude_v_L))
        return {"rpm": float(self.rpm[i]), "amplitude": float(self.amplitude_v_L[i])}

    def to_json(self) -> dict[str, Any]:
        return {"model": self.model, "rpm": [float(r) for r in self.rpm],
                "amplitude_v_L": _finite_or_none(self.amplitude_v_L),
                "amplitude_w_L": _finite_or_none(self.amplitude_w_L), "period": list(self.period),
                "resonance": self.resonance, "dofs": self.dofs, "settled": list(self.settled),
                "elapsed_s": round(self.elapsed_s, 6), "cpu_s": round(self.cpu_s, 6)}

    def to_csv(self, path: Path) -> Path:
        """One row per speed: rpm, v_L and w_L amplitudes (m), period, slip share, settled (1/0)."""
        settled = self.settled or (None,) * len(self.rpm)
        rows = [(f"{r:g}", f"{a:.9e}", f"{b:.9e}", "" if p is None else p, f"{s:.4f}", "" if k is None else int(k))
                for r, a, b, p, s, k in zip(self.rpm, self.amplitude_v_L, self.amplitude_w_L,
                                            self.period, self.slip_fraction, settled)]
        return _write_rows(path, ["rpm", "amplitude_v_L", "amplitude_w_L", "period", "slip_fraction", "settled"],
                           rows, f"{self.model}, {self.dofs} DOF; amplitudes (max - min)/2, m")

    def plot(self, ax=None, **line):
        """v_L amplitude (um) over speed (r/min)."""
        ax = _axes(ax)
        ax.plot(self.rpm, 1e6 * self.amplitude_v_L,
                label=line.pop("label", self.model), color=line.pop("color", MODEL_COLOURS.get(self.model)),
                **line)
        ax.set_xlabel("speed (r/min)")
        ax.set_ylabel("v_L amplitude (um)")
        return ax


@dataclass(frozen=True)
class RingSweepResult:
    """A ring's steady-state tip amplitudes over speed in time (shroud.analysis.ring.run_ring_sweep): blade 0's
    as the single blade's :class:`SweepResult` (its period and slip share, the ring's DOFs; settled: every
    blade's amplitudes), and every blade's."""

    sweep: SweepResult
    blades_amplitude_v_L: np.ndarray     # (speeds, N), m; NaN where the run diverged
    blades_amplitude_w_L: np.ndarray

    @property
    def blades(self) -> int:
        return self.blades_amplitude_v_L.shape[1]

    @property
    def rpm(self) -> np.ndarray:
        return self.sweep.rpm

    @property
    def amplitude_v_L(self) -> np.ndarray:
        return self.sweep.amplitude_v_L

    def to_json(self) -> dict[str, Any]:
        return {**self.sweep.to_json(), "blades": self.blades,
                "blades_amplitude_v_L": [_finite_or_none(row) for row in self.blades_amplitude_v_L],
                "blades_amplitude_w_L": [_finite_or_none(row) for row in self.blades_amplitude_w_L]}

    def to_csv(self, path: Path) -> Path:
        """One row per speed: rpm, then every blade's v_L amplitude (m), settled (1/0)."""
        rows = [(f"{r:g}", *(f"{a:.9e}" for a in row), int(k))
                for r, row, k in zip(self.rpm, self.blades_amplitude_v_L, self.sweep.settled)]
        return _write_rows(path, ["rpm", *(f"amplitude_v_L_{j}" for j in range(self.blades)), "settled"], rows,
                           f"ring of {self.blades} {self.sweep.model} blades, in time; amplitudes (max - min)/2, m")

    def plot(self, ax=None, **line):
        """Every blade's v_L amplitude (um) over speed (r/min): blade 0 as the single blade's curve, the others
        thin behind it."""
        ax = _axes(ax)
        colour = line.pop("color", MODEL_COLOURS.get(self.sweep.model))
        ax.plot(self.rpm, 1e6 * self.blades_amplitude_v_L[:, 1:], color=colour, lw=0.5, alpha=0.5)
        return self.sweep.plot(ax, color=colour, **{"label": f"{self.sweep.model}, {self.blades} blades", **line})


# ----------------------------------------------------------------------------- Campbell

@dataclass(frozen=True)
class CampbellResult:
    """Frequencies tracked over speed by mode shape (MAC), each track labelled at the first speed."""

    rpm: np.ndarray            # (s,) r/min
    f_hz: np.ndarray           # (s, k) tracked frequencies, Hz
    labels: tuple[str, ...]    # (k,) label of each track at the first speed
    coriolis: bool
    elapsed_s: float

    def crossings(self, order: int) -> list[tuple[str, float, float]]:
        """(label, rpm, f_hz) where a track meets the engine-order line f = order * rpm / 60.

        >>> r = CampbellResult(np.array([0.0, 6000.0]), np.array([[100.0], [100.0]]), ("flap1",), False, 0.0)
        >>> r.crossings(2)
        [('flap1', 3000.0, 100.0)]
        """
        out = []
        line = order * self.rpm / 60.0
        for j, label in enumerate(self.labels):
            d = self.f_hz[:, j] - line
            for i in np.flatnonzero(np.sign(d[:-1]) * np.sign(d[1:]) < 0):
                t = d[i] / (d[i] - d[i + 1])
                rpm = self.rpm[i] + t * (self.rpm[i + 1] - self.rpm[i])
                out.append((label, float(rpm), float(order * rpm / 60.0)))
        return out

    def to_json(self) -> dict[str, Any]:
        return {"rpm": [float(r) for r in self.rpm],
                "tracks": {label: [float(f) for f in self.f_hz[:, j]] for j, label in enumerate(self.labels)},
                "coriolis": self.coriolis, "elapsed_s": round(self.elapsed_s, 6)}

    def to_csv(self, path: Path) -> Path:
        """One row per speed: rpm, then each track's frequency (Hz)."""
        rows = [[f"{r:g}", *(f"{f:.6f}" for f in fs)] for r, fs in zip(self.rpm, self.f_hz)]
        return _write_rows(path, ["rpm", *self.labels], rows,
                           f"Campbell diagram, Coriolis {'on' if self.coriolis else 'off'}; Hz")

    def plot(self, ax=None, orders=(), **line):
        """Tracks (Hz) over speed (r/min), with engine-order lines f = k rpm / 60 for k in ``orders``."""
        ax = _axes(ax)
        for j, label in enumerate(self.labels):
            ax.plot(self.rpm, self.f_hz[:, j], label=label, **line)
        for k in orders:
            ax.plot(self.rpm, k * self.rpm / 60.0, color="grey", lw=0.8, ls="--")
        ax.set_xlabel("speed (r/min)")
        ax.set_ylabel("frequency (Hz)")
        return ax


# ----------------------------------------------------------------------------- harmonic balance

def _floats(values: np.ndarray | None, count: int) -> list:
    """JSON numbers of a per-point array (None where nan or inf, or where the array was not taken)."""
    if values is None:
        return [None] * count
    return [float(v) if np.isfinite(v) else None for v in values]


@dataclass(frozen=True)
class HBResult:
    """A steady-state branch over speed by harmonic balance, points in continuation order.

    rpm may go back at a fold; ``stable`` from the Floquet multipliers: True,
    False, or None where the largest |multiplier| lies within its own error
    ``multiplier_error`` of 1 (or a touch grazes: shroud.core.floquet.Stability);
    ``critical`` how each point's largest one lies (shroud.core.floquet.crossing:
    kind, and n = 2 pi / |arg mu| of a complex pair); amplitudes are
    (max - min)/2 over one period, m. ``bifurcations``: where the nominal
    stability (|mu| against 1) changes ({"rpm", "amplitude", "kind"}: fold,
    period-doubling, Neimark-Sacker). ``spectral_tail``: the share (RMS) of
    the contact forces' spectrum above H at the point of the largest contact
    forces (grazing points, whose brief touches are all tail, would say
    nothing). ``kinks``: where the continuation passed a corner of the
    branch ({"rpm", "turn_rad"}: the corner, where the tangent lines either side meet, and the turn between
    them, by more than the step resolves; past pi / 2 the branch folds there); ``folds``: where the speed
    turns back ({"rpm", "kind"}: dp/ds changing sign, "smooth" or at a "corner"; the continuation's,
    independent of the multipliers, whose turning is in ``bifurcations``);
    ``tail_target``: the tail H was chosen for (None: H given), met or not
    (``tail_met``). ``period_map_multiplier``, ``period_map_error``, ``stability_reason``, ``in_time``:
    the verdicts checked against the project's integrator (shroud.analysis.hb.integrator_check).
    """

    model: str
    harmonics: int
    samples: int
    rpm: np.ndarray
    amplitude_v_L: np.ndarray
    amplitude_w_L: np.ndarray
    stable: np.ndarray                 # object: True, False or None (undecided) per point
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
    critical: tuple[tuple[str, float | None], ...] = ()   # per point: floquet.crossing of its multipliers
    multiplier_error: np.ndarray | None = None   # per point: the error of the largest |multiplier|
    amplitude_error: np.ndarray | None = None    # per point: the v_L amplitude's change at 2 H, m (nan: not taken)
    kinks: tuple[dict, ...] = ()
    folds: tuple[dict, ...] = ()
    tail_target: float | None = None
    period_map_multiplier: np.ndarray | None = None   # per point: the integrator's period map's largest |mu|
    period_map_error: np.ndarray | None = None        # ... its error
    stability_reason: tuple[str, ...] = ()            # per point: why the verdict is what it is ("" : the monodromy's)
    in_time: tuple[dict | None, ...] = ()             # per point: the check in time where taken (unstable points)

    def __post_init__(self):      # one spelling of the three verdicts: True, False, None
        object.__setattr__(self, "stable", np.array([None if s is None else bool(s) for s in self.stable], object))

    @classmethod
    def from_points(cls, model, harmonics, samples, rpm, details, iterations, complete, stopped, dofs,
                    condensed, elapsed_s, X=None, kinks=(), folds=()) -> "HBResult":
        from shroud.core.floquet import bifurcation, crossing
        amp = np.array([d["amplitude_v_L"] for d in details])
        bif = []
        for i in range(1, len(details)):
            kind = bifurcation(details[i - 1]["multipliers"], details[i]["multipliers"])
            if kind:
                bif.append({"rpm": 0.5 * (rpm[i - 1] + rpm[i]), "amplitude": 0.5 * (amp[i - 1] + amp[i]),
                            "kind": kind})
        return cls(model=model, harmonics=harmonics, samples=samples, rpm=np.asarray(rpm, float),
                   amplitude_v_L=amp, amplitude_w_L=np.array([d["amplitude_w_L"] for d in details]),
                   stable=np.array([d["stable"] for d in details], object),
                   max_multiplier=np.array([float(np.abs(d["multipliers"]).max(initial=0.0)) for d in details]),
                   bifurcations=tuple(bif),
                   spectral_tail=max(details, key=lambda d: d["force_rms"])["tail"] if details else 0.0,
                   iterations=int(sum(iterations)), complete=complete, stopped=stopped, dofs=dofs,
                   condensed=condensed, elapsed_s=elapsed_s, X=None if X is None else np.array(X),
                   critical=tuple(crossing(d["multipliers"]) for d in details),
                   multiplier_error=np.array([d["multiplier_error"] for d in details], float),
                   amplitude_error=np.array([d.get("amplitude_error", np.nan) for d in details], float),
                   kinks=tuple(kinks), folds=tuple(folds),
                   period_map_multiplier=np.array([d.get("period_map_multiplier", np.nan) for d in details], float),
                   period_map_error=np.array([d.get("period_map_error", np.nan) for d in details], float),
                   stability_reason=tuple(d.get("stability_reason", "") for d in details),
                   in_time=tuple(d.get("in_time") for d in details))

    @property
    def uncertain(self) -> np.ndarray:
        """Per point: stability undecided (within the multipliers' error)."""
        return np.array([s is None for s in self.stable], bool)

    @property
    def tail_met(self) -> bool | None:
        """Whether the spectral tail is within ``tail_target`` (None: no target)."""
        return None if self.tail_target is None else bool(self.spectral_tail <= self.tail_target)

    def _peak(self, points: np.ndarray) -> dict | None:
        """The largest amplitude among ``points`` (mask) with its errors: ``rpm_error`` half the larger step
        to its neighbours (r/min: the peak lies between them); ``amplitude_error`` (m) its change at 2 H
        plus how far the top may rise between the points: for a parabolic top a quarter of its drop to the
        lower neighbour (the top at d from the point, |d| <= h / 2: rise c d^2 <= c h^2 / 4, drop to the
        far neighbour c (h^2 + 2 h |d|) >= c h^2). inf where the change at 2 H was not taken, or where the
        point has fewer than two neighbours (a peak at the branch's end: the top may lie beyond it).
        ``truncation_error`` (m): the change at 2 H alone, the amplitude's error at that very point (nan
        where not taken): what two branches' amplitudes read at one speed (a range's end) may differ by."""
        if not points.any():
            return None
        i = int(np.flatnonzero(points)[np.argmax(self.amplitude_v_L[points])])
        around = [j for j in (i - 1, i + 1) if 0 <= j < len(self.rpm)]
        rpm_error = max((abs(self.rpm[j] - self.rpm[i]) / 2 for j in around), default=0.0)
        truncation = np.inf if self.amplitude_error is None else self.amplitude_error[i]
        error = float("inf")
        if len(around) == 2 and np.isfinite(truncation):
            rise = 0.25 * (self.amplitude_v_L[i] - min(self.amplitude_v_L[j] for j in around))
            error = float(truncation + max(rise, 0.0))
        return {"rpm": float(self.rpm[i]), "amplitude": float(self.amplitude_v_L[i]), "stable": self.stable[i],
                "max_multiplier": float(self.max_multiplier[i]), "rpm_error": float(rpm_error),
                "amplitude_error": error,
                "truncation_error": float(truncation) if np.isfinite(truncation) else float("nan")}

    @property
    def resonance(self) -> dict:
        """The largest v_L amplitude on the points not shown unstable: {"rpm", "amplitude" (m), "stable"
        (True, or None where undecided), "max_multiplier", "rpm_error", "amplitude_error", "truncation_error"
        (:meth:`_peak`),
        "unstable_peak"}: ``unstable_peak`` the largest on unstable points where larger (else None). rpm and
        amplitude are nan where every point is unstable."""
        shown_unstable = np.array([s is False for s in self.stable], bool)
        kept = self._peak(~shown_unstable)
        other = self._peak(shown_unstable)
        if kept is None:
            nan = float("nan")
            kept = {"rpm": nan, "amplitude": nan, "stable": None, "max_multiplier": nan, "rpm_error": nan,
                    "amplitude_error": nan, "truncation_error": nan}
        larger = other is not None and not other["amplitude"] <= kept["amplitude"]
        return {**kept, "unstable_peak": other if larger else None}

    def notes(self) -> list[str]:
        """What a reader must know about how far the branch can be trusted (one sentence each)."""
        out = []
        if not self.complete:
            out.append(f"incomplete: {self.stopped}")
        if self.kinks:
            out.append(f"{len(self.kinks)} kink(s) passed at " + ", ".join(f"{k['rpm']:.0f}" for k in self.kinks)
                       + " r/min (the tangent turned by more than the step resolves)")
        if self.folds:
            out.append(f"{len(self.folds)} fold(s) in speed at " + ", ".join(
                f"{f['rpm']:.0f}" + (" (at a corner)" if f["kind"] == "corner" else "") for f in self.folds) + " r/min")
        if self.tail_met is False:
            out.append(f"spectral tail {self.spectral_tail:.3g} above the target {self.tail_target:g} at the most "
                       f"harmonics tried (H = {self.harmonics})")
        undecided = int(self.uncertain.sum())
        if undecided:
            out.append(f"{undecided} of {len(self.rpm)} points of undecided stability (|multiplier| within its "
                       "error of 1, the two ways disagreeing, or the integrator staying where called unstable)")
        stays = sum(1 for r in self.stability_reason if "stays" in r)
        if stays:
            out.append(f"{stays} point(s) called unstable where the integrator started on them stays: undecided")
        return out

    def to_json(self) -> dict[str, Any]:
        err = self.multiplier_error if self.multiplier_error is not None else np.full(len(self.rpm), np.nan)
        return {"model": self.model, "method": "hb", "harmonics": self.harmonics, "samples": self.samples,
                "rpm": [float(r) for r in self.rpm], "amplitude_v_L": [float(a) for a in self.amplitude_v_L],
                "amplitude_w_L": [float(a) for a in self.amplitude_w_L],
                "stable": [None if s is None else bool(s) for s in self.stable],
                "max_multiplier": [float(m) for m in self.max_multiplier],
                "multiplier_error": [float(e) for e in err],
                "period_map_multiplier": _floats(self.period_map_multiplier, len(self.rpm)),
                "period_map_error": _floats(self.period_map_error, len(self.rpm)),
                "stability_reason": list(self.stability_reason) or [""] * len(self.rpm),
                "in_time": list(self.in_time) or [None] * len(self.rpm),
                "bifurcations": list(self.bifurcations), "resonance": self.resonance,
                "spectral_tail": self.spectral_tail, "harmonics_tried": list(self.harmonics_tried),
                "tail_target": self.tail_target, "tail_met": self.tail_met, "kinks": list(self.kinks),
                "folds": list(self.folds),
                "complete": self.complete, "stopped": self.stopped, "notes": self.notes(),
                "dofs": self.dofs, "condensed": self.condensed, "newton_iterations": self.iterations,
                "elapsed_s": round(self.elapsed_s, 6)}

    def to_csv(self, path: Path) -> Path:
        """One row per branch point: rpm, amplitudes (m), stable (1, 0, or empty: undecided), largest
        |multiplier| and its error."""
        err = self.multiplier_error if self.multiplier_error is not None else np.full(len(self.rpm), np.nan)
        rows = [(f"{r:.6f}", f"{a:.9e}", f"{b:.9e}", "" if s is None else int(s), f"{m:.6f}", f"{e:.6f}")
                for r, a, b, s, m, e in zip(self.rpm, self.amplitude_v_L, self.amplitude_w_L, self.stable,
                                            self.max_multiplier, err)]
        return _write_rows(path, ["rpm", "amplitude_v_L_m", "amplitude_w_L_m", "stable", "max_multiplier",
                                  "multiplier_error"],
                           rows, f"model {self.model}, harmonic balance H = {self.harmonics}")

    def plot(self, ax=None, label: str | None = None, colour=None, scale: float = 1e3, **line):
        """v_L amplitude (mm) over speed: stable stretches solid, unstable dashed, undecided dotted with
        small crosses; bifurcations marked.

        ``line``: further matplotlib line properties (e.g. linewidth).
        """
        ax = _axes(ax)
        drawn = None
        start = 0
        styles = {True: {"linestyle": "-"}, False: {"linestyle": "--"},
                  None: {"linestyle": ":", "marker": "x", "ms": 3.0}}
        for i in range(1, len(self.rpm) + 1):
            if i == len(self.rpm) or self.stable[i] is not self.stable[start]:
                sl = slice(start, min(i + 1, len(self.rpm)))
                drawn, = ax.plot(self.rpm[sl], self.amplitude_v_L[sl] * scale, **styles[self.stable[start]],
                                 color=colour if colour is not None else (drawn.get_color() if drawn else None),
                                 label=label if start == 0 else None, **line)
                start = i
        marks = {"fold": "o", "period-doubling": "s", "Neimark-Sacker": "^"}
        for b in self.bifurcations:       # each kind in the legend once per panel
            named = b["kind"] in ax.get_legend_handles_labels()[1]
            ax.plot(b["rpm"], b["amplitude"] * scale, marks[b["kind"]], color="k", ms=4, mfc="none",
                    label=None if named else b["kind"], zorder=4)
        ax.set_xlabel("speed (r/min)")
        ax.set_ylabel("amplitude of v_L (mm)")
        return ax
