"""Stability and accuracy of the contact treatments on stiff and extreme cases.

For kn from 1e6 to 1e10 N/m, at the paper's step (256 per excitation
period) and coarser ones, with the implicit and explicit treatments: is the
run bounded, does the energy balance close over the last periods (load input
= damping + friction dissipation + stored-energy change, to 1 %), and how far
is v_L from a run at an 8x finer step. Then the extremes: mu = 0, full stick
under a huge preload (must equal the linear blade with the contact springs
added), zero gap, a gap no vibration reaches (must equal the free blade),
and 30000 r/min. Linear references are steady-state frequency-domain
solutions of the same M, C, K (an independent method).
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from shroud import signals
from shroud.api import build_system
from shroud.contact import contact_law
from shroud.plotting import figure, save
from shroud.report import markdown_table, seconds
from shroud.transient import run as run_transient

OPTIONS = {"kn_values": [1e6, 1e7, 1e8, 1e9, 1e10], "steps_per_period": [256, 64, 32, 16],
           "treatments": ["implicit", "explicit"], "refine": 8, "huge_preload_N": 1e5,
           "unreached_gap_m": 0.01, "high_rpm": 30000.0,
           "model": "reduced"}       # any transient model; "fe-reduced": scenes/stability_fe.toml


def linear_amplitude(system, law=None) -> float:
    """v_L amplitude of the linear steady state, with every contact spring stuck if ``law`` is given."""
    K = np.asarray(system.K, float)
    if law is not None and law.count:
        W = np.asarray(system.contact.W, float)
        k_y = np.zeros(law.m)
        for (nr, tr), p in zip(law.rows, law.props):
            k_y[nr] += p[1]
            k_y[tr] += p[2]
        K = K + W.T @ np.diag(k_y) @ W
    w = system.omega_e
    Q = np.linalg.solve(K - w * w * np.asarray(system.M) + 1j * w * np.asarray(system.C), system.f_aero)
    return float(abs(np.asarray(system.tip)[0] @ Q))


def _one(params, spp: int, treatment: str, model: str = "reduced"):
    p = params.updated({"time.steps_per_period": spp, "time.contact": treatment})
    system = build_system(p, model)
    return p, system, run_transient(system, p)


def _error_vs_fine(tr, fine, spp, refine) -> float:
    """max |v_L - v_L(fine)| over the last 10 periods, at the coarse times, / max |v_L(fine)|."""
    coarse = signals.last_periods(tr.tip[:, 0], spp)
    ref = signals.last_periods(fine.tip[:, 0], spp * refine)[::refine]
    return float(np.abs(coarse - ref).max() / np.abs(ref).max())


def _row(label, spp, treatment, tr, fine, refine):
    bounded = tr.diverged is None
    return {"case": label, "steps_per_period": spp, "treatment": treatment, "bounded": bounded,
            "cause": tr.diverged or "",
            "energy_error": tr.energy.relative_error if bounded and tr.energy else float("nan"),
            "error_vs_fine": _error_vs_fine(tr, fine, spp, refine) if bounded else float("nan"),
            "amplitude_v_L_m": signals.amplitude(tr.tip[:, 0], spp) if bounded else float("nan"),
            "time_s": tr.elapsed_s}


def run(scene, out: Path) -> dict:
    params, opts = scene.params, scene.options
    refine = int(opts["refine"])
    rows = []
    for kn in opts["kn_values"]:
        base = params.updated({"contact.kn": kn, "contact.kt": kn * params.contact.kt / params.contact.kn})
        for spp in opts["steps_per_period"]:
            _, _, fine = _one(base, spp * refine, "implicit", opts["model"])
            for treatment in opts["treatments"]:
                _, _, tr = _one(base, spp, treatment, opts["model"])
                rows.append(_row(f"kn {kn:.0e}", spp, treatment, tr, fine, refine))
    spp0 = params.time.steps_per_period
    extremes = {"mu = 0": {"contact.mu": 0.0}, "full stick (huge preload)": {"contact.N0": opts["huge_preload_N"]},
                "zero gap": {"contact.N0": 0.0}, "gap never reached": {"contact.gap": opts["unreached_gap_m"]},
                f"{opts['high_rpm']:g} r/min": {"speed.rpm": opts["high_rpm"]}}
    linear = {}
    for label, change in extremes.items():
        base = params.updated(change)
        _, _, fine = _one(base, spp0 * refine, "implicit", opts["model"])
        for treatment in opts["treatments"]:
            p, system, tr = _one(base, spp0, treatment, opts["model"])
            rows.append(_row(label, spp0, treatment, tr, fine, refine))
            if treatment == "implicit" and label in ("full stick (huge preload)", "gap never reached"):
                law = contact_law(system.contact, p.contact, m=2) if "stick" in label else None
                exact = linear_amplitude(system, law)
                linear[label] = {"transient_m": rows[-1]["amplitude_v_L_m"], "linear_m": exact,
                                 "relative_difference": abs(rows[-1]["amplitude_v_L_m"] - exact) / exact}
    with open(out / "stability.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    fig, axes = figure(1, 2, width=9.0)
    for treatment, ax in zip(opts["treatments"], axes[0]):
        for spp in opts["steps_per_period"]:
            sel = [r for r in rows if r["treatment"] == treatment and r["steps_per_period"] == spp
                   and r["case"].startswith("kn")]
            ax.loglog([float(r["case"][3:]) for r in sel], [r["error_vs_fine"] for r in sel], "o-",
                      label=f"{spp} steps/period")
        ax.set_xlabel("kn (N/m)")
        ax.set_ylabel("error of v_L vs 8x finer step")
        ax.set_title(f"{treatment} contact (missing points: unbounded)")
        ax.legend()
    save(fig, out / "stability.png")
    lines = [f"# {scene.title}\n",
             f"{params.time.periods} periods per run at {params.speed.rpm:g} r/min, N0 = {params.contact.N0:g} N "
             f"unless the case says otherwise; energy balance over the last 10 periods; error = max |v_L - "
             f"v_L(8x finer, implicit)| over the last 10 periods / max |v_L(fine)|.\n",
             markdown_table(["case", "steps/period", "treatment", "bounded", "energy balance error",
                             "error vs 8x finer", "amplitude v_L (mm)", "time"],
                            [(r["case"], r["steps_per_period"], r["treatment"], "yes" if r["bounded"] else
                              f"no ({r['cause']})", r["energy_error"], r["error_vs_fine"],
                              r["amplitude_v_L_m"] * 1e3, seconds(r["time_s"])) for r in rows]),
             "\nLinear limits (frequency-domain steady state of the same matrices):\n",
             markdown_table(["case", "transient amplitude (mm)", "linear amplitude (mm)", "relative difference"],
                            [(k, v["transient_m"] * 1e3, v["linear_m"] * 1e3, v["relative_difference"])
                             for k, v in linear.items()]),
             "![stability.png](stability.png)"]
    (out / "report.md").write_text("\n".join(lines) + "\n")
    return {"rows": rows, "linear_limits": linear}
