"""The ``shroud`` command (docs/interface.md).

Bad input of any kind ends with one line on stderr naming the key and what is
allowed, and exit status 2; nothing is written before the input is checked.
"""

from __future__ import annotations

import argparse
import json
import signal
import sys

import numpy as np

from workbench.compare import DEFAULT_ATOL, DEFAULT_IGNORE, DEFAULT_RTOL
from shroud.analysis.systems import solver
from shroud.base.errors import InputError, RunDiverged

EXIT_RUN_FAILED = 1
EXIT_BAD_INPUT = 2
EXIT_GATE_FAILED = 3        # a gate of `shroud run` or a number of `shroud compare` did not hold
EXIT_INTERRUPTED = 130


class _Parser(argparse.ArgumentParser):
    def error(self, message: str):          # one line, exit 2 (argparse prints usage too)
        raise InputError("command line", message)


def _common(p: argparse.ArgumentParser) -> None:
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="override a parameter (repeatable; SI units unless the key says, values read as TOML), "
                        "e.g. --set speed.rpm=8500 --set contact.gap=1e-4; keys: docs/interface.md")
    p.add_argument("--scene", metavar="FILE", help="TOML scene whose values the --set options override")
    p.add_argument("--json", action="store_true", help="print one JSON object on stdout (logs stay on stderr)")


def build_parser() -> argparse.ArgumentParser:
    from shroud.core import registry
    parser = _Parser(prog="shroud", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    p = sub.add_parser("modal", help="natural frequencies and mode labels at one speed")
    _common(p)
    p.add_argument("--model", choices=registry.names("modal"), default="reduced",
                   help="model to analyse (default reduced)")
    p.add_argument("--rpm", type=float, metavar="RPM", help="rotation speed, r/min (default speed.rpm: 10000)")
    p.add_argument("--modes", type=int, default=6, metavar="K", help="number of modes, lowest first (default 6)")
    p.add_argument("--coriolis", action=argparse.BooleanOptionalAction, default=True,
                   help="with the Coriolis (gyroscopic) coupling: frequencies of the damped rotating "
                        "system (default), or without it")
    p.add_argument("--interface", choices=("free", "stuck"),
                   help="the contact's linear limit: no springs, or every contact as springs kn, kt "
                        "(with ring.blades = N: per nodal diameter; with disk.thickness > 0 the FE sector of "
                        "blade and disk, free unless stuck is asked)")

    p = sub.add_parser("static", help="tip displacement under a force at the blade tip")
    _common(p)
    p.add_argument("--model", choices=registry.names(), default="reduced",
                   help=f"models with a static solve: {', '.join(registry.names('static'))}")
    p.add_argument("--tip-force", type=float, nargs=3, required=True, metavar=("FX", "FY", "FZ"),
                   help="force at the blade tip, N, global X, Y, Z")
    p.add_argument("--rpm", type=float, metavar="RPM", help="rotation speed, r/min (default speed.rpm: 10000)")

    p = sub.add_parser("transient", help="time response with impact and friction")
    _common(p)
    p.add_argument("--model", choices=registry.names("transient"), default="reduced",
                   help="model to integrate (default reduced)")
    p.add_argument("--rpm", type=float, metavar="RPM", help="rotation speed, r/min (default speed.rpm: 10000)")
    p.add_argument("--out", default="out/transient", metavar="DIR",
                   help="folder for the time-series CSV transient_<model>.csv (default out/transient)")

    p = sub.add_parser("sweep", help="steady-state amplitude over a speed range")
    _common(p)
    p.add_argument("--model", choices=registry.names(), default="reduced",
                   help=f"time domain: {', '.join(registry.names('sweep'))}; hb: any, the full solid (fe) "
                        "at --checkpoints only")
    p.add_argument("--rpm-from", type=float, metavar="RPM", help="first speed, r/min (required except with --checkpoints)")
    p.add_argument("--rpm-to", type=float, metavar="RPM", help="last speed, r/min (required except with --checkpoints)")
    p.add_argument("--rpm-count", type=int, metavar="K",
                   help="speeds of the time-domain sweep (required there); with --method hb the least "
                        "number of points on the branch")
    p.add_argument("--method", default="time", metavar="{time,hb}",
                   help="time: run from rest at each speed (default); hb: harmonic balance with continuation")
    p.add_argument("--harmonics", type=int, default=None, metavar="H",
                   help="harmonics H of the excitation frequency kept by --method hb (default 10)")
    p.add_argument("--tail", type=float, default=None, metavar="SHARE",
                   help="--method hb without --harmonics: choose H (5, 10, 20, 40) until the contact forces' "
                        "spectral tail above H is at most this share (a number in (0, 1))")
    p.add_argument("--samples", type=int, default=None, metavar="S",
                   help="time samples per period of --method hb's contact evaluation (default 8 H as a power of 2, >= 512)")
    p.add_argument("--checkpoints", type=float, nargs="+", metavar="RPM",
                   help="--method hb at these speeds only, r/min, no continuation (the full solid: condensed "
                        "exactly on its contact coordinates, Newton started from the fe-reduced state)")

    p = sub.add_parser("section", help="the blade's cross-section at one span position, as the beams use it")
    _common(p)
    p.add_argument("--at", type=float, default=0.0, metavar="X",
                   help="span position x, m from the root, 0 <= X <= blade.length (default 0, the root)")

    p = sub.add_parser("run", help="run a whole scene (a study), or a campaign of scenes, into a folder")
    p.add_argument("scene", help="scene file, or campaign file (it has campaign = [...])")
    p.add_argument("--out", metavar="DIR", help="output folder (default out/<file name>); one run at a time")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="override a parameter or a study option (repeatable; values read as TOML), e.g. "
                        "--set speed.rpm=9000 --set 'options.models=[\"reduced\"]'")
    p.add_argument("--quick", action="store_true", help="a coarse, minute-scale version (the scene's [quick] table)")
    p.add_argument("--gate", action="append", default=[], metavar="'PATH<=VALUE'",
                   help="bound a number of results.json, or require a value (repeatable; PATH<=VALUE, "
                        "PATH>=VALUE or PATH==VALUE, VALUE a number, true, false or a word); exit 3 if it "
                        "does not hold")
    p.add_argument("--json", action="store_true", help="print the run's summary as one JSON object on stdout")

    p = sub.add_parser("compare", help="hold every number, yes/no and word (verdict) of NEW/results.json "
                                       "against BASE/results.json (run times skipped)")
    p.add_argument("base", metavar="BASE", help="output folder of an earlier run (scene or campaign)")
    p.add_argument("new", metavar="NEW", help="output folder of the run to check")
    p.add_argument("--rtol", type=float, default=DEFAULT_RTOL,
                   help=f"relative tolerance (default {DEFAULT_RTOL:g})")
    p.add_argument("--atol", type=float, default=DEFAULT_ATOL,
                   help=f"absolute tolerance (default {DEFAULT_ATOL:g})")
    p.add_argument("--ignore", action="append", default=[], metavar="PATTERN",
                   help="also ignore values whose dotted path matches this glob (repeatable); "
                        "ignored always: run times (keys ending in _s or _time_ratio, values and verdicts "
                        "of unit 'time ratio': drawn from run times) and " + " ".join(DEFAULT_IGNORE))
    p.add_argument("--junit", metavar="FILE", help="write the comparison as JUnit XML")
    p.add_argument("--json", action="store_true", help="print the comparison as one JSON object on stdout")

    p = sub.add_parser("record", help="make again the records of full scenes that the quick-against-full tests "
                                      "hold (tests/data/records), on a clean tree")
    p.add_argument("scenes", nargs="*", metavar="SCENE", help="scene names (default: every recorded scene)")
    p.add_argument("--stale", action="store_true", help="only the records that are missing, not current, or "
                                                        "left behind by a physics change")
    p.add_argument("--check", action="store_true", help="run nothing: say which records are current; "
                                                        "exit 3 if any is not; warn of those a change "
                                                        "of the physics they import has left behind")
    p.add_argument("--jobs", type=int, default=1, help="scenes run side by side (default 1)")
    return parser


# The models that take a NACA section and tapers: the beams, on the sections along the span
# (reduced_model.airfoil.span_sections), the solid (meshes.blade's loft) and the shell (meshes.shell's
# camber surface). A STEP file: the beams, on its slices (reduced_model.step_slices), in every command, and
# the solid's modes (its transient and static need a load per unit span and a shroud volume the file does
# not name).
PROFILE_MODELS = ("reduced", "full", "extended", "fe", "fe-reduced", "shell", "shell-reduced")
STEP_MODELS = ("reduced", "full", "extended")
STEP_MODAL_MODELS = STEP_MODELS + ("fe",)


def _params(args, disk: bool = False):
    from workbench.scene import load_scene
    overrides = list(args.set)
    if getattr(args, "rpm", None) is not None:
        overrides.append(f"speed.rpm={args.rpm}")
    model = getattr(args, "model", None)
    return load_scene(args.scene, overrides, profile=model in PROFILE_MODELS,
                      step=model in (STEP_MODAL_MODELS if args.command == "modal" else STEP_MODELS),
                      disk=disk).params


def _emit(args, payload: dict, text: str) -> None:
    from shroud.base.parallel import mpi_rank
    if mpi_rank() != 0:          # under mpirun every rank holds the result; one prints it
        return
    if args.json:
        print(json.dumps(payload))
    else:
        print(text)


def cmd_modal(args) -> None:
    from shroud.analysis.api import linear_limits, modal
    if args.modes < 1:
        raise InputError("--modes", f"{args.modes} is out of range; allowed: an integer >= 1")
    params = _params(args, disk=True)
    if args.interface is not None or params.disk.thickness > 0:    # the disk sector comes per nodal diameter
        interface = args.interface or "free"
        limit = linear_limits(params, args.model, params.speed.rpm, args.modes, args.coriolis, interface)
        diameters = "".join(f"\n  nd {d['nd']:3d}: " + " ".join(f"{m['f_hz']:.2f}" for m in d["modes"])
                            for d in limit.nodal_diameters or [])
        rows = "\n".join(f"  {m.label:10s} {m.f_hz:12.2f} Hz" for m in limit.blade.modes)
        return _emit(args, limit.to_json(), f"{args.model} model, {params.speed.rpm:g} r/min, interface "
                                            f"{interface}\n{rows}{diameters}")
    result = modal(params, args.model, rpm=params.speed.rpm, n_modes=args.modes, coriolis=args.coriolis)
    rows = "\n".join(f"  {m.label:10s} {m.f_hz:12.2f} Hz" for m in result.modes)
    _emit(args, result.to_json(),
          f"{result.model} model, {result.rpm:g} r/min, {result.dofs} DOF, "
          f"Coriolis {'on' if result.coriolis else 'off'}, {result.elapsed_s:.3f} s\n{rows}")


def cmd_static(args) -> None:
    from shroud.analysis.api import static
    params = _params(args)
    result = static(params, args.model, args.tip_force, rpm=params.speed.rpm)
    tip = result.tip
    _emit(args, result.to_json(),
          f"{result.model} model, {result.rpm:g} r/min, {result.dofs} DOF, {result.elapsed_s:.3f} s\n"
          + "\n".join(f"  {k:4s} {'-' if v is None else f'{v:.6e}'} m" for k, v in tip.items()))


def cmd_transient(args) -> None:
    from shroud.analysis.api import transient
    from workbench.runner import holding, output_folder
    from shroud.base.parallel import mpi_rank
    params = _params(args)
    out = output_folder("transient", args.out)
    writer = mpi_rank() == 0
    csv_path = out / f"transient_{args.model}.csv" if writer else None   # one rank writes
    with holding(out, writer):
        result = transient(params, args.model, csv_path=csv_path)
    payload = result.to_json()
    _emit(args, payload, json.dumps(payload, indent=1))


def cmd_sweep(args) -> int | None:
    from shroud.core import registry
    if args.method not in ("time", "hb"):
        raise InputError("--method", f"{args.method!r} is unknown; allowed: time, hb")
    if args.method == "hb" and args.checkpoints is not None:
        return _sweep_checkpoints(args)
    if args.checkpoints is not None:
        raise InputError("--checkpoints", "speeds solved one by one by harmonic balance; allowed: with --method hb")
    for flag in ("rpm_from", "rpm_to"):
        if getattr(args, flag) is None:
            raise InputError("command line", f"the following arguments are required: --{flag.replace('_', '-')}")
    if args.method == "hb":
        if registry.model(args.model).linear_harmonics is not None:
            raise InputError("--model", f"{args.model} is solved by harmonic balance at single speeds; "
                                        "allowed: --checkpoints RPM [RPM ...] instead of a range")
        return _sweep_hb(args)
    from shroud.analysis.checks import check_speed_count
    if args.model not in registry.names("sweep"):
        raise InputError("--model", f"{args.model} is too costly to rebuild at every speed of a time-domain "
                                    f"sweep; allowed: {', '.join(registry.names('sweep'))}, or --method hb "
                                    "--checkpoints")
    if args.rpm_count is None:
        raise InputError("command line", "the following arguments are required: --rpm-count "
                                         "(with --method time)")
    if args.rpm_count < 1:
        raise InputError("--rpm-count", f"{args.rpm_count} is out of range; allowed: an integer >= 1")
    check_speed_count(args.rpm_count, "--rpm-count")
    if not 0 < args.rpm_from <= args.rpm_to:
        raise InputError("--rpm-from", "allowed: 0 < rpm-from <= rpm-to")
    params = _params(args)
    result = solver("sweep", params)(params, args.model, np.linspace(args.rpm_from, args.rpm_to, args.rpm_count))
    payload = result.to_json()
    _emit(args, payload, json.dumps(payload, indent=1))
    diverged = result.rpm[~np.isfinite(result.amplitude_v_L)]
    if diverged.size:
        print(f"error: run diverged at {diverged.size} of {result.rpm.size} speeds "
              f"({', '.join(f'{r:g}' for r in diverged)} r/min): their amplitudes are null", file=sys.stderr)
        return EXIT_RUN_FAILED


def _sweep_hb(args) -> int:
    from shroud.analysis.checks import check_speed_count
    from shroud.analysis.hb import DEFAULT_HARMONICS, check_inputs
    if args.tail is not None and args.harmonics is not None:
        raise InputError("--tail", "give --harmonics or --tail, not both")
    if args.tail is not None and args.samples is not None:
        raise InputError("--tail", "--samples is chosen with H when --tail chooses H; give one of them")
    H = DEFAULT_HARMONICS if args.harmonics is None else args.harmonics
    check_inputs(H, args.samples, args.rpm_from, args.rpm_to)
    if args.rpm_count is not None and args.rpm_count < 2:
        raise InputError("--rpm-count", f"{args.rpm_count} is out of range; allowed: an integer >= 2 "
                                        "(the least number of points on the branch)")
    if args.rpm_count is not None:
        check_speed_count(args.rpm_count, "--rpm-count")
    params = _params(args)
    if params.speed.rpm_per_s != 0:
        raise InputError("speed.rpm_per_s", "harmonic balance seeks periodic states at constant speed; "
                                            "allowed: 0 with --method hb")
    if args.tail is not None:
        result = solver("continuation to a spectral tail", params)(params, args.model, args.rpm_from, args.rpm_to,
                                                                   args.tail, min_points=args.rpm_count)
    else:
        result = solver("continuation", params)(params, args.model, args.rpm_from, args.rpm_to, H, args.samples,
                                                args.rpm_count)
    payload = result.to_json()
    _emit(args, payload, json.dumps(payload, indent=1))
    if not result.complete:
        print(f"error: the branch is incomplete: {result.stopped}", file=sys.stderr)
        return EXIT_RUN_FAILED


def _sweep_checkpoints(args) -> int | None:
    from shroud.analysis.hb import DEFAULT_HARMONICS, run_checkpoints
    for flag in ("rpm_from", "rpm_to", "rpm_count", "tail"):
        if getattr(args, flag) is not None:
            raise InputError(f"--{flag.replace('_', '-')}", "not used with --checkpoints (single speeds, no "
                                                             "continuation); allowed: --harmonics, --samples")
    if not all(r > 0 for r in args.checkpoints):
        raise InputError("--checkpoints", "allowed: speeds > 0 r/min")
    params = _params(args)
    if params.speed.rpm_per_s != 0:
        raise InputError("speed.rpm_per_s", "harmonic balance seeks periodic states at constant speed; "
                                            "allowed: 0 with --method hb")
    H = DEFAULT_HARMONICS if args.harmonics is None else args.harmonics
    payload = run_checkpoints(params, args.model, args.checkpoints, harmonics=H, samples=args.samples)
    _emit(args, payload, json.dumps(payload, indent=1))
    failed = [c for c in payload["checkpoints"] if not c["converged"]]
    if failed:
        print(f"error: Newton did not converge at {len(failed)} of {len(payload['rpm'])} speeds ("
              + ", ".join(f"{c['rpm']:g} r/min: {c['start']}, |R|/|F| {c['residual']:.3g}" for c in failed)
              + "): their amplitudes are null", file=sys.stderr)
        return EXIT_RUN_FAILED


def cmd_section(args) -> None:
    from reduced_model.airfoil import blade_section, chord_and_thickness
    from workbench.scene import load_scene
    params = load_scene(args.scene, list(args.set), profile=True).params
    blade = params.blade
    if not 0.0 <= args.at <= blade.length:
        raise InputError("--at", f"{args.at!r} m is off the blade; allowed: 0 <= X <= blade.length "
                                 f"({blade.length:g} m)")
    chord, thickness = chord_and_thickness(blade, args.at)
    s = blade_section(blade, args.at)
    kappa = s.shear_coefficients(params.material.nu)
    payload = {"x": args.at, "section": blade.section, "chord": chord, "thickness": thickness, "area": s.area,
               "centroid": list(s.centroid), "I_vv": s.I_v, "I_ww": s.I_w, "I_vw": s.I_vw,
               "principal_angle": s.principal_angle, "J": s.J,
               "J_bounds": None if s.J_bounds is None else list(s.J_bounds), "warping": s.warping,
               "shear_centre": list(s.shear_centre), "shear_coefficients": list(kappa), "method": s.method}
    rows = [("area", s.area, "m^2"), ("I_vv (flap)", s.I_v, "m^4"), ("I_ww (chord)", s.I_w, "m^4"),
            ("I_vw", s.I_vw, "m^4"), ("principal angle", s.principal_angle, "rad"), ("J", s.J, "m^4"),
            ("warping Gamma", s.warping, "m^6")]
    text = [f"{blade.section} section at x = {args.at:g} m: chord {chord:g} m, thickness {thickness:g} m ({s.method})"]
    text += [f"  {name:16s} {value: .6e} {unit}" for name, value, unit in rows]
    text.append(f"  {'centroid':16s} ({s.centroid[0]: .6e}, {s.centroid[1]: .6e}) m (eta_v, eta_w)")
    text.append(f"  {'shear centre':16s} ({s.shear_centre[0]: .6e}, {s.shear_centre[1]: .6e}) m (eta_v, eta_w)")
    text.append(f"  {'kappa (Cowper)':16s} {kappa[0]:.6f} (nearest e_v), {kappa[1]:.6f} (nearest e_w) "
                f"at nu = {params.material.nu:g}")
    if s.J_bounds is not None:
        text.append(f"  {'J bounds':16s} [{s.J_bounds[0]:.6e}, {s.J_bounds[1]:.6e}] m^4")
    _emit(args, payload, "\n".join(text))


def cmd_run(args) -> int:
    from workbench.campaign import is_campaign, run_campaign
    from workbench.gates import from_option, merged
    from workbench.runner import run_scene
    gates = merged(tuple(from_option(text) for text in args.gate))
    run = run_campaign if is_campaign(args.scene) else run_scene
    summary = run(args.scene, out=args.out, overrides=args.set, quick=args.quick, gates=gates)
    records = summary["gates"]
    failed = [r for r in records if not r["passed"]]
    lines = [f"{summary['status']}: {summary['out']}/report.md ({summary['elapsed_s']:.1f} s)"]
    if records:
        lines.append(f"gates: {len(records) - len(failed)} of {len(records)} held; "
                     f"junit.xml in {summary['out']}")
        lines += [f"FAILED {r['scene'] + ': ' if 'scene' in r else ''}{r['path']}: {r['message']}"
                  for r in failed]
    if summary["status"] == "complete with failures":
        lines.append("a scene failed: its error.txt is in its folder")
    _emit(args, summary, "\n".join(lines))
    if summary["status"] == "complete with failures":     # a failed scene outranks a failed gate
        return EXIT_RUN_FAILED
    if summary["status"].startswith("diverged"):
        print(f"error: run {summary['status']}: see {summary['out']}/report.md", file=sys.stderr)
        return EXIT_RUN_FAILED
    return EXIT_GATE_FAILED if failed else 0


def cmd_compare(args) -> int:
    from workbench.compare import compare, markdown
    if not (args.rtol >= 0 and args.atol >= 0):
        raise InputError("--rtol" if not args.rtol >= 0 else "--atol", "allowed: a tolerance >= 0")
    comparison = compare(args.base, args.new, rtol=args.rtol, atol=args.atol,
                         ignore=tuple(args.ignore), junit_path=args.junit)
    _emit(args, comparison.to_json(), markdown(comparison))
    return EXIT_GATE_FAILED if comparison.drifts else 0


def cmd_record(args) -> int:
    from workbench import records
    if args.jobs < 1:
        raise InputError("--jobs", f"{args.jobs} is out of range; allowed: an integer >= 1")
    if not args.check:
        try:
            made = records.record(args.scenes or None, stale_only=args.stale, jobs=args.jobs)
        except RuntimeError as exc:          # a scene that failed: the others' records are made all the same
            print(f"error: {exc}", file=sys.stderr)
            return EXIT_RUN_FAILED
        for path in made:
            print(path.relative_to(records.ROOT))
        return 0
    stale, behind = 0, []
    for scene in args.scenes or records.RECORDED:
        path = records.RECORDS / f"{scene}.json"
        record = records.load(scene) if path.is_file() else None
        problems = records.check(record).problems if record else ("missing",)
        stale += bool(problems)
        changed = records.physics_changes(record) if record else ()
        behind += [scene] if changed else []
        physics = ("physics not recorded (made before digests)" if changed is None else
                   f"physics changed since: {', '.join(changed)}" if changed else "physics as recorded")
        print(f"{scene}: " + ("current" if not problems else "; ".join(problems))
              + (f"; {physics}; {records.decided(record['conclusions'])}" if record else ""))
    if behind:               # a warning: the quick tests hold the physics; the records are made again before it lands
        print(f"warning: records a physics change has left behind, to make again before it lands: "
              f"shroud record {' '.join(behind)}")
    return EXIT_GATE_FAILED if stale else 0


def main(argv: list[str] | None = None) -> int:
    try:
        args = build_parser().parse_args(argv)
        if args.command != "compare":
            from shroud.base.cache import check_cache
            check_cache()                # a cache that cannot be written stops the run before any work
        return {"modal": cmd_modal, "static": cmd_static, "transient": cmd_transient, "sweep": cmd_sweep,
                "section": cmd_section, "run": cmd_run, "compare": cmd_compare, "record": cmd_record}[args.command](args) or 0
    except InputError as exc:
        print(exc.line(), file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        signal.signal(signal.SIGINT, signal.SIG_IGN)     # the run is over: a repeated Ctrl-C must not cut the exit
        print("error: interrupted (any output folder holds a result marked partial)", file=sys.stderr)
        return EXIT_INTERRUPTED
    except RunDiverged as exc:
        print(f"error: run diverged: {exc}", file=sys.stderr)
        return EXIT_RUN_FAILED


if __name__ == "__main__":
    sys.exit(main())
