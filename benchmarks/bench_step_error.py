"""The reference's own step error, against the reduced solid's that error_vs_time measures it by (issue 33).

comparisons/error_vs_time.py bounds each error of its step ladders by the
reference's distance from the time-exact solution of its model, measured on
the scene's step ladder of the reduced solid (StepError): the change from
each rung to the next finer. This runs the reference itself (the P2 solid)
at the finest step and at half of it, beside the reduced solid's ladder, and
prints the two step-halving changes in the study's norm (the worst NRMSE on
the reference's window and ranges), so the stand-in can be held against the
thing it stands for:

    OMP_NUM_THREADS=1 python benchmarks/bench_step_error.py            # full scene: 256 steps, ~5 min
    OMP_NUM_THREADS=1 python benchmarks/bench_step_error.py --quick    # quick scene: 128 steps, ~2 min

Measured (load ~5 on 2 cores): full scene (at 4e2eac1, by the probe this
script was made from), the P2 solid's change from 128 to 256 steps per
period 0.00409, the reduced solid's 0.00407 (and 0.0169 from 64 to 128);
quick scene (``--quick``, 140 s), from 64 to 128: the P2 solid's 0.01710, the
reduced solid's 0.01704 (and 0.0870 from 32 to 64).
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from comparisons.error_vs_time import Point, distance, measure, on_window, reference_point, spans
from shroud.analysis import api
from shroud.analysis.agreement import signals_of
from workbench.scene import load_scene

SCENE = Path(__file__).resolve().parents[1] / "scenes" / "error_vs_time.toml"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="the quick scene's steps per period")
    args = parser.parse_args()
    scene = load_scene(SCENE, quick=args.quick)
    params, o = scene.params, scene.options
    period = 2 * math.pi / (params.load.ke * params.speed.omega)
    finest = reference_point(o)
    spp = params.with_overrides(list(finest.overrides)).time.steps_per_period
    space = tuple(k for k in finest.overrides if not k.startswith("time."))
    half = Point(finest.model, "reference at half its steps", space + (f"time.steps_per_period={spp // 2}",))
    api.compile_kernels(params, ["fe-reduced"])
    runs = {}
    for name, point in [("solid", finest), ("solid, half", half)] + [
            (f"reduced solid {s}", Point("fe-reduced", f"{s}", (f"time.steps_per_period={s}",)))
            for s in (spp // 4, spp // 2, spp)]:
        result, _, cost, _ = measure(params, point, warm=point.model != "fe")
        runs[name] = result.trajectory
        print(f"{name}: {cost:.1f} s", flush=True)
    t_ref = runs["solid"].t
    window = {k: on_window(tr.t, signals_of(tr), t_ref, period, o["window_periods"]) for k, tr in runs.items()}
    ranges = spans(window["solid"])
    print(f"P2 solid, {spp // 2} -> {spp} steps/period: {distance(window['solid, half'], window['solid'], ranges):.5f}")
    for coarse, fine in ((spp // 4, spp // 2), (spp // 2, spp)):
        change = distance(window[f"reduced solid {coarse}"], window[f"reduced solid {fine}"], ranges)
        print(f"reduced solid, {coarse} -> {fine} steps/period: {change:.5f}")


if __name__ == "__main__":
    main()
