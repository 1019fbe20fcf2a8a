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

The study is compute (:func:`compute` -> :class:`StabilityResult`) ->
plot (:func:`plot`) -> report (:func:`report`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from comparisons._study import study
from shroud.core.verdict import Verdict
from shroud.analysis.api import build_system
from shroud.analysis.transient import contact_law_for
from shroud.analysis.transient import run as run_transient
from shroud.base.errors import InputError
from shroud.base.markdown import markdown_table, seconds
from shroud.core import signals
from shroud.core.newmark import LAG_CHECK_MAX_DOFS, NewmarkScheme, explicit_lag_stability, stuck_stiffness
from shroud.core.plotting import figure, save
from shroud.base.tables import write_records

OPTIONS = {"kn_values": [1e6, 1e7, 1e8, 1e9, 1e10], "steps_per_period": [256, 64, 32, 16],
           "treatments": ["implicit", "explicit"], "refine": 8, "huge_preload_N": 1e5,
           "unreached_gap_m": 0.01, "high_rpm": 30000.0,
           "model": "reduced"}       # any transient model; "fe-reduced": scenes/stability_fe.toml

TREATMENTS = ("implicit", "explicit")


ENERGY_CLOSED = 1e-6    # the energy balance closes when its residual is below this share of the input work
LINEAR_LIMIT = 1e-2     # a transient meets its linear limit when its amplitude is within 1 % of it


def linear_limit(relative_difference: float, step_error: float) -> Verdict:
    """Whether a transient's steady amplitude meets the exact linear one to LINEAR_LIMIT; the margin is the
    transient's own step error (its largest v_L difference from a run at ``refine`` times the steps)."""
    return Verdict.of(relative_difference, LINEAR_LIMIT, step_error, below=True, above=False,
                      reason="margin: the transient's step error, measured against a finer-step run")


@dataclass(frozen=True)
class Case:
    """One family of runs: a label for the report, the parameter changes, the exact reference if any."""

    label: str
    changes: dict
    kn: float | None = None            # the kn sweep's stiffness, N/m (None: an extreme case)
    linear_reference: str | None = None   # "stuck": linear blade + contact springs; "free": without contact


@dataclass(frozen=True)
class StabilityResult:
    rows: list[dict]                   # one per (case, steps per period, treatment)
    linear_limits: dict[str, dict]     # case label -> transient vs linear amplitude
    explicit_lag: list[dict]           # the lag analysis, one row per (kn, steps per period)
    left_out: list[str] = field(default_factory=list)   # what was not computed, and why

    def conclusions(self) -> dict:
        """What the report concludes, as data: implicit bounded and its energy balance closed (to
        1e-6, a verdict with the summed work's round-off as margin) everywhere; whether the explicit
        treatment diverges anywhere, and at each kn and step (events, not thresholds); each linear limit
        met to 1 % (a verdict with the transient's measured step error as margin)."""
        implicit = [r for r in self.rows if r["treatment"] == "implicit"]
        explicit = [r for r in self.rows if r["treatment"] == "explicit"]
        worst = max(implicit, key=lambda r: r["energy_error"] if np.isfinite(r["energy_error"]) else -np.inf,
                    default=None)
        rows = {(r["case"], r["treatment"]): r for r in implicit}
        return {"implicit_bounded": all(r["bounded"] for r in implicit),
                "implicit_energy_closed": None if worst is None else Verdict.of(
                    worst["energy_error"], ENERGY_CLOSED, worst["steps"] * np.finfo(float).eps, below=True,
                    above=False, reason="the balance's residual over the input work; margin: the round-off of "
                                        "work summed over the run's steps (steps x machine epsilon)"),
                "explicit_diverges_somewhere": any(not r["bounded"] for r in explicit),
                "explicit_bounded": {f"{r['case']}, {r['steps_per_period']} steps": r["bounded"] for r in explicit},
                "linear_limit_met": {k: linear_limit(v["relative_difference"], rows[(k, "implicit")]["error_vs_fine"])
                                     for k, v in self.linear_limits.items()}}

    def to_json(self) -> dict:
        return {"rows": self.rows, "linear_limits": self.linear_limits, "explicit_lag": self.explicit_lag,
                "left_out": self.left_out, "conclusions": self.conclusions()}


def check(scene) -> None:
    """The study varies the contact: it needs one, and treatments it knows."""
    p, o = scene.params, scene.options
    if not p.contact.enabled or p.shroud.thickness == 0:
        raise InputError("contact.enabled", "the stability study varies the contact stiffness and treatment; "
                         "it needs contact (contact.enabled = true and shroud.thickness > 0)")
    unknown = [t for t in o["treatments"] if t not in TREATMENTS]
    if unknown or not o["treatments"]:
        raise InputError("options.treatments", f"{o['treatments']!r}; allowed: a non-empty list from "
                         f"{', '.join(TREATMENTS)}")
    if int(o["refine"]) < 2:
        raise InputError("options.refine", f"{o['refine']!r}; allowed: an integer >= 2 (the reference run's "
                         "step is this many times finer)")


def linear_amplitude(system, law=None) -> float:
    """v_L amplitude of the linear steady state, with every contact spring stuck if ``law`` is given."""
    K = np.asarray(system.K, float)
    if law is not None and law.count:
        W = np.asarray(system.contact.W, float)
        K = K + W.T @ stuck_stiffness(law) @ W
    w = system.omega_e
    Q = np.linalg.solve(K - w * w * np.asarray(system.M) + 1j * w * np.asarray(system.C), system.f_aero)
    return float(abs(np.asarray(system.tip)[0] @ Q))


def lag_estimate(system, law, dt: float) -> dict:
    """The energy estimate of the explicit treatment's least damped mode, stuck contacts.

    Modes of the continuous quadratic eigenproblem (M, C, K + W^T D W) give each
    mode's structural damping ratio and the contact springs' share r of its
    stiffness; the lag removes r sin(Omega dt)/2 with Omega dt = 2 atan(omega dt/2)
    the average-acceleration step's discrete phase. Returns the mode with the
    smallest net ratio.
    """
    M, C, K = (np.asarray(A, float) for A in (system.M, system.C, system.K))
    Kc = np.asarray(system.contact.W, float).T @ stuck_stiffness(law) @ np.asarray(system.contact.W, float)
    n = M.shape[0]
    Minv = np.linalg.inv(M)
    s, V = np.linalg.eig(np.block([[np.zeros((n, n)), np.eye(n)], [-Minv @ (K + Kc), -Minv @ C]]))
    keep = s.imag > 0
    s, V = s[keep], V[:n, keep]
    zeta = -s.real / np.abs(s)
    share = np.array([(v.conj() @ Kc @ v).real / (v.conj() @ (K + Kc) @ v).real for v in V.T])
    lag = share * np.sin(2 * np.arctan(np.abs(s) * dt / 2)) / 2
    i = int(np.argmin(zeta - lag))
    return {"frequency_hz": float(abs(s[i]) / (2 * np.pi)), "zeta_structural": float(zeta[i]),
            "share": float(share[i]), "zeta_lag": float(lag[i]), "zeta_net": float(zeta[i] - lag[i])}


def lag_analysis(params, kn_values, spp_values, model: str) -> tuple[list[dict], str | None]:
    """The explicit treatment's lag against the structural damping, stuck contacts, per kn and step.

    Returns the rows and, when the analysis had to be left out, why.
    """
    rows = []
    for kn in kn_values:
        for spp in spp_values:
            p = params.updated({"contact.kn": kn, "contact.kt": kn * params.contact.kt / params.contact.kn,
                                "time.steps_per_period": spp})
            system = build_system(p, model)
            if not isinstance(system.K, np.ndarray) or system.dofs > LAG_CHECK_MAX_DOFS:
                return [], (f"the lag eigen-analysis needs a dense model of at most {LAG_CHECK_MAX_DOFS} DOF "
                            f"(its 3n x 3n eigen-solves); the {model} model has {system.dofs} "
                            f"{'dense' if isinstance(system.K, np.ndarray) else 'sparse'} DOF")
            law = contact_law_for(system, p.contact)
            lag = explicit_lag_stability(system, law, NewmarkScheme(p.time_step))
            est = lag_estimate(system, law, p.time_step)
            rows.append({"kn": kn, "steps_per_period": spp, "frequency_hz": est["frequency_hz"],
                         "zeta_structural": est["zeta_structural"], "share": est["share"],
                         "zeta_lag_estimate": est["zeta_lag"], "zeta_net_estimate": est["zeta_net"],
                         "frequency_hz_eigen": lag.frequency_hz,
                         "zeta_net_eigen": lag.damping_ratio, "time_step": p.time_step,
                         "steps_per_mode_period": 1.0 / (est["frequency_hz"] * p.time_step),
                         "stable_time_step": lag.dt_stable,
                         "steps_per_period_needed": int(np.ceil(spp * p.time_step / lag.dt_stable))})
    return rows, None


def _one(params, spp: int, treatment: str, model: str = "reduced"):
    p = params.updated({"time.steps_per_period": spp, "time.contact": treatment})
    system = build_system(p, model)
    return p, system, run_transient(system, p)


def _error_vs_fine(tr, fine, spp, refine) -> float:
    """max |v_L - v_L(fine)| over the last 10 periods, at the coarse times, / max |v_L(fine)|."""
    coarse = signals.last_periods(tr.tip[:, 0], spp)
    ref = signals.last_periods(fine.tip[:, 0], spp * refine)[::refine]
    return float(np.abs(coarse - ref).max() / np.abs(ref).max())


def _row(case: Case, spp, treatment, tr, fine, refine):
    bounded = tr.diverged is None
    return {"case": case.label, "kn": case.kn, "steps_per_period": spp, "treatment": treatment,
            "bounded": bounded, "cause": tr.diverged or "",
            "energy_error": tr.energy.relative_error if bounded and tr.energy else float("nan"),
            "error_vs_fine": _error_vs_fine(tr, fine, spp, refine) if bounded else float("nan"),
            "amplitude_v_L_m": signals.amplitude(tr.tip[:, 0], spp) if bounded else float("nan"),
            "steps": len(tr.tip) - 1, "time_s": tr.elapsed_s}


def cases(params, opts) -> list[tuple[Case, list[int]]]:
    """Every case with the steps per period it runs at: the kn sweep, then the extremes."""
    ratio = params.contact.kt / params.contact.kn
    sweep = [(Case(f"kn {kn:.0e}", {"contact.kn": kn, "contact.kt": kn * ratio}, kn=kn),
              list(opts["steps_per_period"])) for kn in opts["kn_values"]]
    spp0 = [params.time.steps_per_period]
    extremes = [Case("mu = 0", {"contact.mu": 0.0}),
                Case("full stick (huge preload)", {"contact.N0": opts["huge_preload_N"]}, linear_reference="stuck"),
                Case("zero gap", {"contact.N0": 0.0}),
                Case("gap never reached", {"contact.gap": opts["unreached_gap_m"]}, linear_reference="free"),
                Case(f"{opts['high_rpm']:g} r/min", {"speed.rpm": opts["high_rpm"]})]
    return sweep + [(c, spp0) for c in extremes]


def compute(scene) -> StabilityResult:
    params, opts = scene.params, scene.options
    refine, model = int(opts["refine"]), opts["model"]
    rows, linear, left_out = [], {}, []
    for case, spps in cases(params, opts):
        base = params.updated(case.changes)
        for spp in spps:
            _, _, fine = _one(base, spp * refine, "implicit", model)
            for treatment in opts["treatments"]:
                p, system, tr = _one(base, spp, treatment, model)
                rows.append(_row(case, spp, treatment, tr, fine, refine))
                if case.linear_reference and treatment == "implicit":
                    law = contact_law_for(system, p.contact) if case.linear_reference == "stuck" else None
                    exact = linear_amplitude(system, law)
                    linear[case.label] = {"reference": case.linear_reference,
                                          "transient_m": rows[-1]["amplitude_v_L_m"], "linear_m": exact,
                                          "relative_difference": abs(rows[-1]["amplitude_v_L_m"] - exact) / exact}
    if "implicit" not in opts["treatments"]:
        left_out.append("linear limits: they are checked on the implicit runs, and none was asked for")
    lag = []
    if "explicit" in opts["treatments"]:
        lag, why = lag_analysis(params, opts["kn_values"], opts["steps_per_period"], model)
        if why:
            left_out.append(f"explicit lag analysis: {why}")
        for r in lag:
            run_row = next((x for x in rows if x["kn"] == r["kn"] and x["treatment"] == "explicit"
                            and x["steps_per_period"] == r["steps_per_period"]), None)
            r["explicit_run_bounded"] = run_row["bounded"] if run_row else None
    return StabilityResult(rows=rows, linear_limits=linear, explicit_lag=lag, left_out=left_out)


def plot(result: StabilityResult, scene, out: Path) -> list[str]:
    """Error against the 8x finer run over kn, one panel per treatment, one line per step; the runs as CSV."""
    opts = scene.options
    write_records(out / "stability.csv", result.rows)
    fig, axes = figure(1, len(opts["treatments"]), width=4.5 * len(opts["treatments"]))
    for treatment, ax in zip(opts["treatments"], axes[0]):
        for spp in opts["steps_per_period"]:
            sel = [r for r in result.rows if r["treatment"] == treatment and r["steps_per_period"] == spp
                   and r["kn"] is not None]
            ax.loglog([r["kn"] for r in sel], [r["error_vs_fine"] for r in sel], "o-",
                      label=f"{spp} steps/period")
        ax.set_xlabel("kn (N/m)")
        ax.set_ylabel(f"error of v_L vs {opts['refine']}x finer step")
        ax.set_title(f"{treatment} contact (missing points: unbounded)")
        ax.legend()
    return [save(fig, out / "stability.png").name]


def report(result: StabilityResult, scene, files: list[str]) -> str:
    params, refine = scene.params, scene.options["refine"]
    rows, linear = result.rows, result.linear_limits
    lines = [f"# {scene.title}\n",
             f"{params.time.periods} periods per run at {params.speed.rpm:g} r/min, N0 = {params.contact.N0:g} N "
             f"unless the case says otherwise; energy balance over the last 10 periods; error = max |v_L - "
             f"v_L({refine}x finer, implicit)| over the last 10 periods / max |v_L(fine)|.\n",
             markdown_table(["case", "steps/period", "treatment", "bounded", "energy balance error",
                             f"error vs {refine}x finer", "amplitude v_L (mm)", "time"],
                            [(r["case"], r["steps_per_period"], r["treatment"], "yes" if r["bounded"] else
                              f"no ({r['cause']})", r["energy_error"], r["error_vs_fine"],
                              r["amplitude_v_L_m"] * 1e3, seconds(r["time_s"])) for r in rows])]
    if linear:
        lines += ["\nLinear limits (frequency-domain steady state of the same matrices):\n",
                  markdown_table(["case", "transient amplitude (mm)", "linear amplitude (mm)", "relative difference"],
                                 [(k, v["transient_m"] * 1e3, v["linear_m"] * 1e3, v["relative_difference"])
                                  for k, v in linear.items()])]
    lines += [f"![{f}]({f})" for f in files]
    lines += _conclusion_lines(result, params.time.periods)
    if result.left_out:
        lines += ["\n**Left out of this run:**\n", *[f"- {why}" for why in result.left_out], ""]
    lines += _lag_section(result.explicit_lag)
    return "\n".join(lines) + "\n"


def _conclusion_lines(result: StabilityResult, periods: int) -> list[str]:
    """The conclusions (:meth:`StabilityResult.conclusions`) in words, with what the run length leaves open."""
    found = result.conclusions()
    implicit = [r for r in result.rows if r["treatment"] == "implicit"]
    explicit = found["explicit_bounded"]
    lines = ["\n## What the runs conclude\n"]
    if implicit:
        bounded = "bounded in every run" if found["implicit_bounded"] else "unbounded in some runs"
        lines.append(f"- Implicit: {bounded}; energy balance closed below {ENERGY_CLOSED:g}: "
                     f"{found['implicit_energy_closed'].sentence()}.")
    if explicit:
        grown = [k for k, v in explicit.items() if not v]
        lines.append(f"- Explicit: unbounded in {len(grown)} of {len(explicit)} runs"
                     + (f"; bounded over {periods} periods: {', '.join(k for k, v in explicit.items() if v)}"
                        if len(grown) < len(explicit) else "") + ".")
        weak = [f"kn {r['kn']:.0e}, {r['steps_per_period']} steps" for r in result.explicit_lag
                if r["explicit_run_bounded"] and r["zeta_net_eigen"] < 0]
        if weak:
            lines.append(f"- Bounded over {periods} periods is not shown stable: {', '.join(weak)} stayed "
                         "bounded although its contact mode has a negative net damping with the contacts stuck "
                         "(lag analysis below); a longer run may grow.")
    for case, met in found["linear_limit_met"].items():
        lines.append(f"- {case}: the transient meets its linear limit to {100 * LINEAR_LIMIT:g} %: {met.sentence()}"
                     + ("" if met.answer is True else f"; more than {periods} periods may be needed for its "
                        "start-up to die, or finer steps") + ".")
    return lines


run = study(compute, plot, report)


def _lag_section(lag: list[dict]) -> list[str]:
    if not lag:
        return []
    resolved = [r for r in lag if r["steps_per_mode_period"] >= 20]
    agree = max((abs(r["zeta_net_estimate"] - r["zeta_net_eigen"]) for r in resolved), default=float("nan"))
    return ["\n## Why the explicit treatment diverges: the one-step lag is a negative damping\n",
            "The explicit step applies the contact force of the step's start. A spring force lagged by dt "
            "does the work pi kn Y^2 sin(omega dt) per cycle on the blade, the work of a negative viscous "
            "damping kn sin(omega dt)/omega ~ kn dt. For the stuck blade's contact mode (frequency omega, "
            "contact springs' share r of its stiffness) that is a damping ratio -r sin(omega dt)/2 ~ "
            "-r pi/(steps per mode period); average-acceleration Newmark adds no numerical damping, so the "
            "run grows when it exceeds the structural (Rayleigh) ratio alpha/(2 omega) + beta omega/2 of "
            "that mode. Estimate (structural ratio from the continuous eigenproblem minus the lag term) "
            "against the eigenvalues of the explicit step's amplification matrix (stuck contacts), and "
            "against the nonlinear runs above:\n",
            markdown_table(["kn (N/m)", "steps/period", "least damped mode (Hz)", "steps per its period",
                            "contact share r", "structural zeta", "lag zeta r sin(W dt)/2", "net zeta (estimate)",
                            "amplification matrix: mode (Hz)", "net zeta",
                            "stable below dt (s)", "steps/period needed", "explicit run bounded"],
                           [(f"{r['kn']:.0e}", r["steps_per_period"], r["frequency_hz"],
                             r["steps_per_mode_period"], r["share"], r["zeta_structural"],
                             r["zeta_lag_estimate"], r["zeta_net_estimate"], r["frequency_hz_eigen"],
                             r["zeta_net_eigen"],
                             r["stable_time_step"], r["steps_per_period_needed"],
                             {True: "yes", False: "no", None: "-"}[r["explicit_run_bounded"]]) for r in lag]),
            f"\nLargest difference between the estimate and the amplification matrix where the mode has "
            f">= 20 steps per period: {agree:.2g} (the energy estimate assumes a small phase lag; on "
            "coarser resolution the lag also shifts the modes and only the matrix is to be believed). "
            "The stuck-contact analysis is conservative for the nonlinear run: while the contacts are "
            "open the lag does nothing, so a weakly unstable case can stay bounded (with its error "
            "against the fine implicit run in the table above). Conclusion: the explicit treatment's instability is "
            "the lag's negative damping, not a step too coarse to resolve the contact: unstable cases "
            "resolve their contact mode with as many as "
            f"{max((r['steps_per_mode_period'] for r in lag if r['zeta_net_eigen'] < 0), default=0):.0f} "
            "steps per period, yet the net damping is negative. integrate() runs this eigen-check before an "
            "explicit run on a dense model and names the cause and the stable step in its warning.\n"]
