"""The HB studies' bifurcations started in time: does the project's integrator stay on the points either
side of each (issue 32)? Kept apart from comparisons._hb so that the studies that ask it (hb_fig4,
hb_gap_preload) name it among their sources, not every study of the shared helpers."""

from __future__ import annotations

from shroud.core.verdict import NOT_DECIDED


def bifurcations_in_time(branch, params, model: str) -> list[dict]:
    """Every bifurcation of ``branch`` checked in time: the branch points on both sides of each
    (shroud.analysis.hb.bifurcation_points) started in the project's integrator for 100 periods
    (shroud.analysis.hb.check_in_time). Per point: rpm, amplitude_m, the branch's ``stable`` there, the
    run's answer ("stays", "leaves" or not decided) with its two verdicts (shroud.core.period_map.InTime,
    JSON) and ``contradicts``: the
    branch calls it unstable and the integrator stays, or stable and the integrator leaves. A model the
    integrator cannot be started on (shroud.analysis.hb.startable) gives an empty list."""
    from shroud.analysis.hb import SpeedModel, bifurcation_points, check_in_time, model_at_speed, startable
    points = bifurcation_points(branch)
    if not points or not startable(*SpeedModel(model_at_speed(params, model), branch.harmonics).at(
            float(branch.rpm[points[0]]))[:2]):
        return []
    out = []
    for i, check in zip(points, check_in_time(params, model, branch, points)):
        answer, stable = check.answer, branch.stable[i]
        out.append({"rpm": float(branch.rpm[i]), "amplitude_m": float(branch.amplitude_v_L[i]), "stable": stable,
                    "in_time": check.to_json(),
                    "contradicts": (stable is False and answer == "stays") or (stable is True and answer == "leaves")})
    return out


def in_time_line(checked: list[tuple[str, list[dict]]]) -> str:
    """One sentence of :func:`bifurcations_in_time` over named branches: how many points the integrator
    confirmed and which it contradicts."""
    points = [(name, p) for name, ps in checked for p in ps]
    if not points:
        return "No bifurcation to check in time."
    bad = [f"{name} {p['rpm']:.0f} r/min ({'stable' if p['stable'] else 'unstable'}, {p['in_time']['answer']})"
           for name, p in points if p["contradicts"]]
    undecided = sum(p["in_time"]["answer"] == NOT_DECIDED for _, p in points)
    return (f"Bifurcations checked in time (the integrator started on the points either side, 100 periods): "
            f"{len(points)} points, {len(points) - len(bad) - undecided} confirmed, {undecided} not decided, "
            f"contradicted at {len(bad)}" + (": " + "; ".join(bad) if bad else "") + ".")
