"""Campbell diagram of the beam model, with and without Coriolis.

Frequencies of the lowest modes over a speed range, tracked by MAC
(reduced_model.campbell), with the engine-order lines f = k_e rpm / 60 of
the excitation (k_e = 2 obstacles in the paper) and the speeds where they
cross a mode: the resonances the Fig. 4 sweeps pass through. Option
``with_fe`` overlays our 3D solid's frequencies at a few speeds, matched by
label (shroud.analysis.api.modal(params, "fe")).
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from reduced_model.campbell import campbell
from shroud.base.errors import InputError
from shroud.core.plotting import MODEL_COLOURS, figure, save
from shroud.base.markdown import markdown_table, seconds

OPTIONS = {
    "rpm_from": 0.0,
    "rpm_to": 15000.0,
    "speeds": 200,
    "n_modes": 4,
    "excitation_orders": [2],          # k_e lines drawn and crossed
    "with_fe": False,
    "fe_rpms": [0.0, 5000.0, 10000.0, 15000.0],
}


def check(scene) -> None:
    o = scene.options
    if not 0 <= o["rpm_from"] < o["rpm_to"]:
        raise InputError("options.rpm_from", f"{o['rpm_from']!r}; allowed: 0 <= rpm_from < rpm_to")
    if o["speeds"] < 2:
        raise InputError("options.speeds", f"{o['speeds']!r}; allowed: an integer >= 2")
    if not 1 <= o["n_modes"] <= 5 * scene.params.reduced.N - 4:
        raise InputError("options.n_modes", f"{o['n_modes']!r}; allowed: 1..{5 * scene.params.reduced.N - 4}")
    if any(k < 1 for k in o["excitation_orders"]):
        raise InputError("options.excitation_orders", f"{o['excitation_orders']!r}; allowed: integers >= 1")


def fe_points(params, rpms, n_modes) -> list[dict]:
    """Our solid's frequencies by label at a few speeds (loads the FE stack)."""
    from shroud.analysis.api import modal
    out = []
    for rpm in rpms:
        result = modal(params.updated({"speed.rpm": rpm}), "fe", rpm=rpm, n_modes=n_modes + 2)
        out.append({"rpm": rpm, "f_hz": result.by_label(), "elapsed_s": result.elapsed_s, "dofs": result.dofs})
    return out


def run(scene, out: Path) -> dict:
    params, o = scene.params, scene.options
    rpms = np.linspace(o["rpm_from"], o["rpm_to"], o["speeds"])
    plain = campbell(params, rpms, o["n_modes"], coriolis=False)
    gyro = campbell(params, rpms, o["n_modes"], coriolis=True)
    fe = fe_points(params, o["fe_rpms"], o["n_modes"]) if o["with_fe"] else []

    with open(out / "campbell.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["rpm"] + [f"{lab}_hz" for lab in plain.labels]
                   + [f"{lab}_coriolis_hz" for lab in gyro.labels]
                   + [f"ke{k}_line_hz" for k in o["excitation_orders"]])
        for i, rpm in enumerate(rpms):
            w.writerow([rpm, *plain.f_hz[i], *gyro.f_hz[i], *(k * rpm / 60 for k in o["excitation_orders"])])
    crossings = {str(k): [{"label": lab, "rpm": r, "f_hz": f} for lab, r, f in gyro.crossings(k)]
                 for k in o["excitation_orders"]}
    shift = 100 * (gyro.f_hz - plain.f_hz) / plain.f_hz
    _figure(plain, gyro, fe, o["excitation_orders"], out / "campbell.png")
    (out / "report.md").write_text(_report(scene, plain, gyro, fe, crossings, shift))
    return {"rpm": rpms, "labels": list(plain.labels), "f_hz": plain.f_hz.T, "f_coriolis_hz": gyro.f_hz.T,
            "coriolis_shift_pct_at_max_rpm": dict(zip(gyro.labels, shift[-1])),
            "crossings": crossings, "fe": fe,
            "elapsed_s": {"without_coriolis": plain.elapsed_s, "with_coriolis": gyro.elapsed_s}}


def _figure(plain, gyro, fe, orders, path: Path) -> None:
    fig, axes = figure(1, 1, height=4.2)
    ax = axes[0, 0]
    for j, lab in enumerate(plain.labels):
        ax.plot(plain.rpm, plain.f_hz[:, j], color=MODEL_COLOURS["reduced"], lw=1.0,
                label="beam, no Coriolis" if j == 0 else None)
        ax.plot(gyro.rpm, gyro.f_hz[:, j], color=MODEL_COLOURS["full"], ls="--", lw=1.0,
                label="beam, with Coriolis" if j == 0 else None)
        ax.annotate(lab, (plain.rpm[-1], plain.f_hz[-1, j]), fontsize=7, ha="right", va="bottom")
    for k in orders:
        ax.plot(plain.rpm, k * plain.rpm / 60, color="k", lw=0.8, ls=":", label=f"{k} x rotation")
        for lab, rpm, f in gyro.crossings(k):
            ax.plot(rpm, f, "o", color="k", ms=4)
            ax.annotate(f"{rpm:.0f} r/min", (rpm, f), fontsize=7, xytext=(4, -10), textcoords="offset points")
    for j, point in enumerate(fe):
        freqs = [point["f_hz"][lab] for lab in plain.labels if lab in point["f_hz"]]
        ax.plot([point["rpm"]] * len(freqs), freqs, "s", color=MODEL_COLOURS["fe"], ms=4,
                label="3D FE" if j == 0 else None)
    ax.set_xlabel("rotation speed (r/min)")
    ax.set_ylabel("frequency (Hz)")
    ax.set_ylim(0, 1.1 * plain.f_hz.max())
    ax.legend(loc="upper left")
    save(fig, path)


def _report(scene, plain, gyro, fe, crossings, shift) -> str:
    rpm = plain.rpm
    picks = sorted({0, len(rpm) // 3, 2 * len(rpm) // 3, len(rpm) - 1})
    rows = [[f"{rpm[i]:.0f}", *(f"{plain.f_hz[i, j]:.1f} / {gyro.f_hz[i, j]:.1f} ({shift[i, j]:+.3f} %)"
                                for j in range(len(plain.labels)))] for i in picks]
    cross = [[k, c["label"], f"{c['rpm']:.0f}", f"{c['f_hz']:.1f}"] for k, cs in crossings.items() for c in cs]
    text = [f"# {scene.title or 'Campbell diagram'}\n",
            f"Beam model (5N = {5 * scene.params.reduced.N} DOF), {len(rpm)} speeds from {rpm[0]:g} to "
            f"{rpm[-1]:g} r/min, modes tracked by MAC and named by their tip kinematics at the first speed.\n",
            "![Campbell diagram](campbell.png)\n",
            "## Frequencies, without / with Coriolis (Hz)\n",
            markdown_table(["rpm", *plain.labels], rows),
            "\nCoriolis couples the radial stretch with the in-plane (Y) bending only; with the stiff "
            "radial direction it moves the bending modes by the amounts shown (a fraction of a percent).\n",
            "\n## Excitation-line crossings (with Coriolis)\n",
            markdown_table(["k_e", "mode", "rpm", "f (Hz)"], cross) if cross else "None in the range.\n"]
    if fe:
        text += ["\n## Our 3D FE at a few speeds (Hz)\n",
                 markdown_table(["rpm", *plain.labels, "DOF", "time"],
                                [[f"{p['rpm']:.0f}", *(p["f_hz"].get(lab) for lab in plain.labels),
                                  p["dofs"], seconds(p["elapsed_s"])] for p in fe])]
    text += ["\n## Cost\n",
             f"Without Coriolis {seconds(plain.elapsed_s)}, with Coriolis {seconds(gyro.elapsed_s)} "
             f"for {len(rpm)} speeds (symmetric eigen-solve, resp. state-space eigen-solve, per speed).\n"]
    return "\n".join(text)
