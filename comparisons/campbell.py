"""Campbell diagram of the beam model, with and without Coriolis.

Frequencies of the lowest modes over a speed range, tracked by MAC
(reduced_model.campbell), with the engine-order lines f = k rpm / 60 for
k in ``excitation_orders`` (1..8); the study's excitation order load.ke
(k_e = 2 obstacles in the paper) is highlighted and its crossings with every
mode marked: the resonances the Fig. 4 sweeps pass through. Option
``with_fe`` overlays our 3D solid's frequencies at a few speeds, matched by
label (shroud.analysis.api.modal(params, "fe")): every mode the beam also
has, plus the solid's torsion modes (the beam has none). The solid's
crossings come from a Southwell fit f^2 = f0^2 + S (rpm/60)^2 through its
points, the form a rotating blade's frequencies follow.

The study is compute (:func:`compute` -> :class:`CampbellComparison`) -> plot -> report.
"""

from __future__ import annotations

import csv
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from comparisons import paper
from comparisons._study import study
from reduced_model.campbell import CampbellResult, campbell
from shroud.base.errors import InputError
from shroud.core.plotting import MODEL_COLOURS, figure, save
from shroud.base.markdown import markdown_table, seconds
from shroud.base.outputs import open_replacing
from shroud.core.verdict import BandVerdict, Verdict

OPTIONS = {
    "rpm_from": 0.0,
    "rpm_to": 15000.0,
    "speeds": 200,
    "n_modes": 4,
    "excitation_orders": [1, 2, 3, 4, 5, 6, 7, 8],   # engine-order lines drawn (load.ke highlighted)
    "with_fe": False,
    "fe_rpms": [0.0, 5000.0, 10000.0, 15000.0],
}
FREQUENCY_TOLERANCE = 0.02   # a beam's frequencies against a reference: table1's criterion (within 2 % of the paper)
TRUNCATION_ERROR = 0.64      # %, the paper's largest modal-truncation error at N = 6 (Sect. 2.1, Table 1)
EIGEN_TOLERANCE = 1e-6       # %, the eigen-solves' relative accuracy (1e-8) in %


def check(scene) -> None:
    o = scene.options
    if not 0 <= o["rpm_from"] < o["rpm_to"]:
        raise InputError("options.rpm_from", f"{o['rpm_from']!r}; allowed: 0 <= rpm_from < rpm_to")
    if o["speeds"] < 2:
        raise InputError("options.speeds", f"{o['speeds']!r}; allowed: an integer >= 2")
    if not 1 <= o["n_modes"] <= 5 * scene.params.reduced.N - 4:
        raise InputError("options.n_modes", f"{o['n_modes']!r}; allowed: 1..{5 * scene.params.reduced.N - 4}")
    if o["with_fe"] and len(o["fe_rpms"]) < 2:
        raise InputError("options.fe_rpms", f"{o['fe_rpms']!r}; allowed: at least two speeds (the Southwell fit)")
    if any(k < 1 for k in o["excitation_orders"]):
        raise InputError("options.excitation_orders", f"{o['excitation_orders']!r}; allowed: integers >= 1")


def fe_points(params, rpms, n_modes) -> list[dict]:
    """Our solid's frequencies by label at a few speeds (loads the FE stack): enough modes that the
    torsion modes below the beam's highest mode are among them."""
    from shroud.analysis.api import modal
    out = []
    for rpm in rpms:
        result = modal(params.updated({"speed.rpm": rpm}), "fe", rpm=rpm, n_modes=n_modes + 2)
        out.append({"rpm": rpm, "f_hz": result.by_label(), "elapsed_s": result.elapsed_s, "dofs": result.dofs})
    return out


def southwell(rpms, f_hz) -> tuple[float, float]:
    """Least-squares (f0^2 in Hz^2, S) of f^2 = f0^2 + S (rpm/60)^2 (Southwell's relation)."""
    A = np.column_stack([np.ones(len(rpms)), (np.asarray(rpms, float) / 60.0) ** 2])
    (f0sq, s), *_ = np.linalg.lstsq(A, np.asarray(f_hz, float) ** 2, rcond=None)
    return float(f0sq), float(s)


def southwell_crossing(f0sq: float, s: float, order: int, rpm_to: float) -> float | None:
    """Speed (r/min) where f^2 = f0^2 + S (rpm/60)^2 meets f = order rpm / 60, or None beyond ``rpm_to``."""
    if order ** 2 <= s:
        return None
    rpm = 60.0 * np.sqrt(f0sq / (order ** 2 - s))
    return float(rpm) if rpm <= rpm_to else None


def fe_tracks(fe: list[dict], beam_labels, f_max: float) -> list[str]:
    """The solid's labels to show: every one the beam also has, plus the torsion modes below ``f_max`` (Hz)."""
    seen = dict.fromkeys(lab for p in fe for lab in p["f_hz"])
    return [lab for lab in seen if lab in beam_labels or
            (lab.startswith("torsion") and min(p["f_hz"].get(lab, np.inf) for p in fe) < f_max)]


def spread(ys: list[float], gap: float) -> list[float]:
    """Positions as close to ``ys`` as keeps neighbours at least ``gap`` apart (order kept)."""
    order = np.argsort(ys)
    y = np.asarray(ys, float)[order]
    for i in range(1, len(y)):
        y[i] = max(y[i], y[i - 1] + gap)
    out = np.empty_like(y)
    out[order] = y
    return list(out)


@dataclass(frozen=True)
class CampbellComparison:
    """The beam's frequencies over speed with and without Coriolis, the solid's points, the crossings."""

    ke: int                        # the excitation order load.ke
    orders: list[int]              # the engine orders drawn (ke among them)
    rpm_to: float                  # the range's top speed, r/min
    plain: CampbellResult          # without Coriolis
    gyro: CampbellResult           # with Coriolis
    fe: list[dict]                 # the solid's frequencies by label at a few speeds (fe_points)
    tracks: list[str]              # the solid's labels shown (fe_tracks)
    fits: dict[str, tuple[float, float]]   # label -> Southwell fit (f0^2, S) of the solid's points

    @property
    def crossings(self) -> dict[str, list[dict]]:
        """Per engine order the beam's crossings (label, r/min, Hz), with Coriolis."""
        return {str(k): [{"label": lab, "rpm": r, "f_hz": f} for lab, r, f in self.gyro.crossings(k)]
                for k in self.orders}

    @property
    def fe_crossings(self) -> dict[str, float | None]:
        return {lab: southwell_crossing(*fit, self.ke, self.rpm_to) for lab, fit in self.fits.items()}

    @property
    def shift(self) -> np.ndarray:
        """Coriolis's frequency shift, %, per speed and mode."""
        return 100 * (self.gyro.f_hz - self.plain.f_hz) / self.plain.f_hz

    def beam_crossing(self, label: str, every: int = 1) -> float | None:
        """The beam's (with Coriolis) crossing of ``label`` with k_e x rotation, r/min, read on every
        ``every``-th speed of the grid; None where it has none."""
        grid = replace(self.gyro, rpm=self.gyro.rpm[::every], f_hz=self.gyro.f_hz[::every])
        return next((r for lab, r, _ in grid.crossings(self.ke) if lab == label), None)

    def speed_band(self, rpm: float, label: str) -> float:
        """FREQUENCY_TOLERANCE carried to the crossing speed, %: a frequency f (1 + e) moves the crossing of
        f(rpm) with k_e rpm / 60 by e / (1 - s), s = d ln f / d ln rpm the beam's slope there."""
        j, rpms = self.gyro.labels.index(label), self.gyro.rpm
        at = rpms > 0
        slope = np.interp(rpm, rpms[at], np.gradient(np.log(self.gyro.f_hz[at, j]), np.log(rpms[at])))
        return 100 * FREQUENCY_TOLERANCE / (1 - slope)

    def verdicts(self) -> dict:
        """flap1's k_e crossing, the beam's, against the paper's resonance (Fig. 11a, 8500 r/min) and against
        the solid's (Southwell fit), within Table 1's 2 % on frequency carried to speed; Coriolis's largest
        frequency shift against the paper's modal-truncation error."""
        out = {"coriolis_negligible": Verdict.of(
            float(np.abs(self.shift).max()), threshold=TRUNCATION_ERROR, margin=EIGEN_TOLERANCE, below=True,
            above=False, unit="%", reason="largest frequency shift by Coriolis over the modes and speeds against the "
                                          f"paper's largest modal-truncation error {TRUNCATION_ERROR:g} % (Table 1), "
                                          "margin the eigen-solves' accuracy")}
        beam = self.beam_crossing("flap1")
        if beam is None:
            return out
        grid = abs(beam - (self.beam_crossing("flap1", every=2) or np.inf)) / beam   # the step doubled
        band = self.speed_band(beam, "flap1")
        words = {"above": "beam higher", "below": "beam lower", "between": "the same"}
        # the paper's own crossing by Table 1 (flap1 284.2 Hz at 8500 r/min against 2 x 8500 / 60) moved from
        # the 8500 r/min its Fig. 11a names: how well the paper knows its resonant speed
        line = self.ke * paper.FIG11_RESONANCE_RPM / 60.0
        own = (paper.TABLE1_REDUCED[6][0] / line - 1) * band / (100 * FREQUENCY_TOLERANCE)   # e / (1 - s)
        out["flap1_resonance_against_paper"] = BandVerdict(
            100 * (beam / paper.FIG11_RESONANCE_RPM - 1), band=band, margin=100 * (grid + abs(own)), unit="%",
            reason=f"the beam's flap1 crossing with {self.ke} x rotation against the paper's resonance at "
                   f"{paper.FIG11_RESONANCE_RPM:g} r/min (Fig. 11a); band Table 1's 2 % on frequency carried to "
                   "speed, margin the crossing's change on every other speed plus the paper's own (its Table 1's "
                   "284.2 Hz crosses the line there)", **words)
        solid = self.fe_crossings.get("flap1")
        if solid is not None:
            f0sq, s = self.fits["flap1"]
            pts = [(p["rpm"], p["f_hz"]["flap1"]) for p in self.fe if "flap1" in p["f_hz"]]
            fit = max(abs(np.sqrt(f0sq + s * (r / 60) ** 2) / f - 1) for r, f in pts)
            out["flap1_resonance_against_solid"] = BandVerdict(
                100 * (beam / solid - 1), band=band, margin=100 * (grid + fit * band / (100 * FREQUENCY_TOLERANCE)),
                unit="%", reason=f"the beam's flap1 crossing with {self.ke} x rotation against the solid's "
                                 "(Southwell fit of its points); band Table 1's 2 % on frequency carried to speed, "
                                 "margin the beam's crossing's change on every other speed plus the fit's largest "
                                 "residual carried to speed", **words)
        return out

    def conclusions(self) -> dict:
        crossings, ke = self.crossings, self.ke
        beam_ke = {lab: next((c["rpm"] for c in crossings[str(ke)] if c["label"] == lab), None)
                   for lab in self.gyro.labels}
        return {"ke": ke, "beam_crossings_rpm": beam_ke, "solid_crossings_rpm": self.fe_crossings,
                "beam_crossings_every_order_rpm": {f"{k}x {c['label']}": c["rpm"] for k in self.orders
                                                   for c in crossings[str(k)]},
                **{name: v.to_json() for name, v in self.verdicts().items()}}

    def to_json(self) -> dict:
        plain, gyro = self.plain, self.gyro
        return {"rpm": plain.rpm, "labels": list(plain.labels), "f_hz": plain.f_hz.T, "f_coriolis_hz": gyro.f_hz.T,
                "coriolis_shift_pct_at_max_rpm": dict(zip(gyro.labels, self.shift[-1])),
                "crossings": self.crossings, "fe": self.fe,
                "fe_southwell": {lab: {"f0_hz": float(np.sqrt(max(a, 0.0))), "S": b}
                                 for lab, (a, b) in self.fits.items()},
                "conclusions": self.conclusions(),
                "elapsed_s": {"without_coriolis": plain.elapsed_s, "with_coriolis": gyro.elapsed_s}}


def compute(scene) -> CampbellComparison:
    """The beam over the speed range with and without Coriolis; the solid at a few speeds if asked."""
    params, o = scene.params, scene.options
    ke = params.load.ke
    rpms = np.linspace(o["rpm_from"], o["rpm_to"], o["speeds"])
    plain = campbell(params, rpms, o["n_modes"], coriolis=False)
    gyro = campbell(params, rpms, o["n_modes"], coriolis=True)
    fe = fe_points(params, o["fe_rpms"], o["n_modes"]) if o["with_fe"] else []
    tracks = fe_tracks(fe, plain.labels, float(gyro.f_hz.max()))
    fits = {lab: southwell([p["rpm"] for p in fe if lab in p["f_hz"]], [p["f_hz"][lab] for p in fe if lab in p["f_hz"]])
            for lab in tracks if sum(lab in p["f_hz"] for p in fe) >= 2}
    return CampbellComparison(ke=ke, orders=sorted(set(o["excitation_orders"]) | {ke}), rpm_to=o["rpm_to"],
                          plain=plain, gyro=gyro, fe=fe, tracks=tracks, fits=fits)


def plot(result: CampbellComparison, scene, out: Path) -> list[str]:
    """The Campbell diagram (campbell.png); the frequencies and engine-order lines as CSV."""
    plain, gyro, orders = result.plain, result.gyro, result.orders
    with open_replacing(out / "campbell.csv") as fh:
        w = csv.writer(fh)
        w.writerow(["rpm"] + [f"{lab}_hz" for lab in plain.labels]
                   + [f"{lab}_coriolis_hz" for lab in gyro.labels]
                   + [f"ke{k}_line_hz" for k in orders])
        for i, rpm in enumerate(plain.rpm):
            w.writerow([rpm, *plain.f_hz[i], *gyro.f_hz[i], *(k * rpm / 60 for k in orders)])
    return [_figure(plain, gyro, result.fe, result.tracks, result.fits, orders, result.ke, out / "campbell.png").name]


def report(result: CampbellComparison, scene, files: list[str]) -> str:
    verdicts = ["\n## Verdicts\n"] + [f"- `{name}`: {v.sentence()}" for name, v in result.verdicts().items()]
    return _report(scene, result.plain, result.gyro, result.fe, result.tracks, result.crossings,
                   result.fe_crossings, result.shift, result.ke) + "\n".join(verdicts) + "\n"


run = study(compute, plot, report)


def _figure(plain, gyro, fe, tracks, fits, orders, ke, path: Path) -> Path:
    fig, axes = figure(1, 1, width=7.4, height=5.0)
    ax = axes[0, 0]
    rpm = plain.rpm
    top = 1.08 * max(plain.f_hz.max(), max((f for p in fe for lab, f in p["f_hz"].items() if lab in tracks),
                                           default=0.0))
    right: list[tuple[float, str, str]] = []      # (y at the right edge, text, colour)
    for k in orders:
        main = k == ke
        ax.plot(rpm, k * rpm / 60, color="k" if main else "0.6", lw=1.4 if main else 0.6, ls="-" if main else ":",
                label=f"{k} x rotation (k_e, the excitation)" if main else ("engine orders 1..8" if k == orders[0]
                                                                            or (k == 2 and ke == 1) else None),
                zorder=2 if main else 1)
        if k * rpm[-1] / 60 > top:                     # leaves through the top: labelled there
            ax.annotate(f"{k}x", (60 * top / k, top), fontsize=6.5, color="k" if main else "0.45", va="bottom",
                        annotation_clip=False)
        else:
            right.append((k * rpm[-1] / 60, f"{k}x", "k" if main else "0.45"))
    for j, lab in enumerate(plain.labels):
        ax.plot(rpm, plain.f_hz[:, j], color=MODEL_COLOURS["reduced"], lw=1.0,
                label="beam, no Coriolis" if j == 0 else None, zorder=3)
        ax.plot(rpm, gyro.f_hz[:, j], color=MODEL_COLOURS["full"], ls="--", lw=1.0,
                label="beam, with Coriolis" if j == 0 else None, zorder=3)
        right.append((plain.f_hz[-1, j], lab, "k"))
    for lab, r, f in gyro.crossings(ke):
        ax.plot(r, f, "o", color="k", ms=5, zorder=5)
        ax.annotate(f"{lab}: {r:.0f} r/min", (r, f), fontsize=7, xytext=(6, -12), textcoords="offset points",
                    bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": "none", "alpha": 0.8}, zorder=6)
    fine = np.linspace(rpm[0], rpm[-1], 100)
    # labels in the right margin, each at its curve's end, spread so that none overlaps another
    for i, lab in enumerate(tracks):
        pts = [(p["rpm"], p["f_hz"][lab]) for p in fe if lab in p["f_hz"]]
        torsion = lab.startswith("torsion")
        ax.plot(*zip(*pts), "D" if torsion else "s", color=MODEL_COLOURS["fe"], ms=4, mfc="none" if torsion else None,
                label=("3D solid, torsion" if torsion else "3D solid") if lab == next(
                    t for t in tracks if t.startswith("torsion") == torsion) else None, zorder=4)
        if lab in fits:
            a, s = fits[lab]
            ax.plot(fine, np.sqrt(np.maximum(a + s * (fine / 60) ** 2, 0.0)), color=MODEL_COLOURS["fe"], lw=0.5,
                    ls="-." if torsion else "-", zorder=3)
            cross = southwell_crossing(a, s, ke, rpm[-1])
            if cross is not None:
                ax.plot(cross, ke * cross / 60, "x", color=MODEL_COLOURS["fe"], ms=7, mew=1.5, zorder=5)
        if torsion:
            right.append((pts[-1][1], f"{lab} (solid)", "k"))
    ax.set_xlabel("rotation speed (r/min)")
    ax.set_ylabel("frequency (Hz)")
    ax.set_xlim(rpm[0], rpm[-1])
    ax.set_ylim(0, top)
    x_text = rpm[-1] + 0.03 * (rpm[-1] - rpm[0])
    for (y, text, colour), y_text in zip(right, spread([r[0] for r in right], 0.03 * top)):
        ax.annotate(text, (rpm[-1], y), xytext=(x_text, y_text), textcoords="data", fontsize=6.5, color=colour,
                    va="center", annotation_clip=False,
                    arrowprops={"arrowstyle": "-", "lw": 0.4, "color": "0.6", "shrinkA": 0, "shrinkB": 0})
    ax.plot([], [], "x", color=MODEL_COLOURS["fe"], ms=7, mew=1.5, label="solid crossing (Southwell fit)")
    ax.plot([], [], "o", color="k", ms=5, label="beam crossing")
    ax.legend(loc="center left", bbox_to_anchor=(0.0, 0.62), fontsize=7, framealpha=0.95)
    fig.subplots_adjust(right=0.86)
    return save(fig, path)


def _report(scene, plain, gyro, fe, tracks, crossings, fe_crossings, shift, ke) -> str:
    rpm = plain.rpm
    picks = sorted({0, len(rpm) // 3, 2 * len(rpm) // 3, len(rpm) - 1})
    rows = [[f"{rpm[i]:.0f}", *(f"{plain.f_hz[i, j]:.1f} / {gyro.f_hz[i, j]:.1f} ({shift[i, j]:+.3f} %)"
                                for j in range(len(plain.labels)))] for i in picks]
    main = {c["label"]: c for c in crossings[str(ke)]}
    cross = [[lab, f"{main[lab]['rpm']:.0f} r/min, {main[lab]['f_hz']:.1f} Hz" if lab in main else
              f"none below {rpm[-1]:.0f} r/min" if lab in plain.labels else "(no such mode)",
              (f"{fe_crossings[lab]:.0f} r/min" if fe_crossings.get(lab) else f"none below {rpm[-1]:.0f} r/min")
              if lab in fe_crossings else "-"] for lab in dict.fromkeys([*plain.labels, *tracks])]
    others = [[k, c["label"], f"{c['rpm']:.0f}", f"{c['f_hz']:.1f}"] for k, cs in crossings.items() if int(k) != ke
              for c in cs]
    step = rpm[1] - rpm[0]
    text = [f"# {scene.title or 'Campbell diagram'}\n",
            f"Beam model (5N = {5 * scene.params.reduced.N} DOF), {len(rpm)} speeds from {rpm[0]:g} to "
            f"{rpm[-1]:g} r/min, modes tracked by MAC and named by their tip kinematics at the first speed. "
            f"Engine-order lines 1..{max(int(k) for k in crossings)}; the excitation k_e = {ke} is drawn bold "
            "and its crossings with every mode are marked.\n",
            "![Campbell diagram](campbell.png)\n",
            f"## Crossings with the excitation line k_e = {ke} (resonances)\n",
            markdown_table(["mode", "beam (with Coriolis)", "3D solid (Southwell fit of its points)"], cross),
            f"\nThe beam's crossings are interpolated between speeds {step:.0f} r/min apart (what this speed "
            "grid resolves); the solid's come from the fit f^2 = f0^2 + S (rpm/60)^2 through its "
            f"{len(fe)} speeds. The beam has no torsion mode (its torsion is restrained, as the paper's); "
            "the solid's torsion modes are shown for where they would resonate.\n" if fe else
            f"\nThe beam's crossings are interpolated between speeds {step:.0f} r/min apart.\n",
            "## Frequencies, without / with Coriolis (Hz)\n",
            markdown_table(["rpm", *plain.labels], rows),
            "\nCoriolis couples the radial stretch with the in-plane (Y) bending only; with the stiff "
            "radial direction it moves the bending modes by the amounts shown (a fraction of a percent).\n",
            "\n## Other engine orders: crossings (with Coriolis)\n",
            markdown_table(["k", "mode", "rpm", "f (Hz)"], others) if others else "None in the range.\n"]
    if fe:
        text += ["\n## Our 3D FE at a few speeds (Hz)\n",
                 markdown_table(["rpm", *tracks, "DOF", "time"],
                                [[f"{p['rpm']:.0f}", *(p["f_hz"].get(lab) for lab in tracks),
                                  p["dofs"], seconds(p["elapsed_s"])] for p in fe])]
    text += ["\n## Cost\n",
             f"Without Coriolis {seconds(plain.elapsed_s)}, with Coriolis {seconds(gyro.elapsed_s)} "
             f"for {len(rpm)} speeds (symmetric eigen-solve, resp. state-space eigen-solve, per speed).\n"]
    return "\n".join(text)
