"""Cost of the shell model against the solid, side by side in one run (issue 25's goals).

Every figure is a whole ``shroud`` process (fresh processes, meshes and caches
on disk as a user has them after a first run, which is made once untimed),
the shell's and the solid's alternated so that both see the same machine load;
the load (``uptime``) is printed with each section, since the machine is shared.
Beside the wall time each process's CPU time (user + system, of every rank
under mpirun) is given: on a loaded machine the wall time also counts the
time a process waited for a core, the CPU time does not, so it is the figure
that tells what the process costs when a core is free (its wall time then is
the CPU time plus its waits for the disk; under mpirun MPI's busy-waiting
counts as CPU).

1. Modal, ``shroud modal --model M --rpm 8500 --modes 5``, M = shell, fe
   (the defaults: shell 4 mm, solid hex 5 mm, first five frequencies within
   0.9 % of each other): median wall time and peak resident memory over
   ``--repeats``, their ratios, the frequencies of each. Goal for the shell:
   < 2 s, < 1 GB (the solid's: 3.5 s, 0.7 GB on a quiet machine).
2. ``--reduced``: ``shroud transient --model M`` (100 periods of the Fig. 8
   case), M = shell-reduced, fe-reduced, their reduction bases built in the
   cache by the untimed first run: medians of the whole process and of the
   integration. Goal for the shell: < 2 s.
3. ``--full``: ``mpirun -n 2 shroud transient --model M`` (100 periods),
   M = shell (4 mm) and fe on the Fig. 8 scene's own 10 mm hexahedra
   (scenes/fig8.toml; the solid's 247 s), once each (minutes). Goal for the
   shell: < 60 s.

    python benchmarks/bench_shell.py
    python benchmarks/bench_shell.py --repeats 5 --reduced --full
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

BIN = Path(sys.executable).parent
SHROUD, MPIRUN = str(BIN / "shroud"), str(BIN / "mpirun")
FIG8_SOLID = ["--set", "fe.mesh_size=0.01"]        # the Fig. 8 scene's solid mesh (scenes/fig8.toml)


def children_cpu() -> float:
    """User + system CPU time (s) of this process's finished children, all of them."""
    ru = resource.getrusage(resource.RUSAGE_CHILDREN)
    return ru.ru_utime + ru.ru_stime


def whole_process(args: list[str], ranks: int = 1) -> tuple[float, float, dict, float]:
    """(wall s, peak RSS GB of the largest process, its JSON, CPU s of all its processes) of one
    ``shroud`` command on ``ranks`` processes."""
    launch = [MPIRUN, "-n", str(ranks)] if ranks > 1 else []
    t0, cpu0 = time.perf_counter(), children_cpu()
    r = subprocess.run(["/usr/bin/time", "-f", "%M", *launch, SHROUD, *args, "--json"], capture_output=True,
                       text=True, env=dict(os.environ, OMP_NUM_THREADS="1"))
    wall, cpu = time.perf_counter() - t0, children_cpu() - cpu0
    if r.returncode != 0:
        raise SystemExit(r.stderr)
    rss_kb = float(r.stderr.strip().splitlines()[-1])
    return wall, rss_kb / 1e6, json.loads(r.stdout.strip().splitlines()[-1]), cpu


def load() -> str:
    """The machine's load as ``uptime`` prints it."""
    return subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()


def alternated(command: dict[str, list[str]], repeats: int, ranks: int = 1) -> dict[str, list]:
    """Each command once untimed (meshes, JIT, caches), then ``repeats`` rounds of all, alternated."""
    for m in command:
        whole_process(command[m], ranks)
    runs = {m: [] for m in command}
    for _ in range(repeats):
        for m in command:
            runs[m].append(whole_process(command[m], ranks))
    return runs


def side_by_side(title: str, runs: dict[str, list], shell: str, solid: str, goal_s: float, extra) -> None:
    """Medians (wall, integration when the JSON has it), peak memory, the solid / shell ratios, the goal."""
    med = {m: statistics.median(r[0] for r in runs[m]) for m in runs}
    own = {m: statistics.median(r[2].get("elapsed_s", float("nan")) for r in runs[m]) for m in runs}
    cpu = {m: statistics.median(r[3] for r in runs[m]) for m in runs}
    rss = {m: max(r[1] for r in runs[m]) for m in runs}
    print(f"{title}; {len(runs[shell])} run(s) each; {load()}")
    for m in runs:
        js = runs[m][0][2]
        print(f"  {m:13s} {js['dofs']:6d} DOF  whole process {med[m]:7.2f} s (all: "
              + ", ".join(f"{r[0]:.2f}" for r in runs[m]) + f")  CPU {cpu[m]:7.2f} s (all: "
              + ", ".join(f"{r[3]:.2f}" for r in runs[m]) + f")  own elapsed {own[m]:7.2f} s  {rss[m]:5.2f} GB  "
              + extra(js))
    print(f"  ratio {solid} / {shell}: whole process {med[solid] / med[shell]:.2f}, CPU {cpu[solid] / cpu[shell]:.2f}, "
          f"own elapsed {own[solid] / own[shell]:.2f}, memory {rss[solid] / rss[shell]:.2f}")
    print(f"  goal {shell} < {goal_s:g} s whole process: wall {'met' if med[shell] < goal_s else 'MISSED'}"
          f" (at this load), CPU {cpu[shell]:.2f} s {'<' if cpu[shell] < goal_s else '>='} {goal_s:g} s")


def modal(repeats: int) -> None:
    command = {m: ["modal", "--model", m, "--rpm", "8500", "--modes", "5"] for m in ("shell", "fe")}
    runs = alternated(command, repeats)
    f = {m: {x["label"]: x["f_hz"] for x in runs[m][0][2]["modes"]} for m in runs}
    side_by_side("modal, 8500 r/min, 5 modes", runs, "shell", "fe", 2.0,
                 lambda js: "  ".join(f"{x['label']} {x['f_hz']:.1f}" for x in js["modes"]))
    print("  shell against solid: " + ", ".join(f"{k} {100 * (f['shell'][k] / f['fe'][k] - 1):+.2f} %"
                                             for k in f["fe"] if k in f["shell"]))
    print(f"  goal shell < 1 GB: {'met' if max(r[1] for r in runs['shell']) < 1.0 else 'MISSED'}")


def transient_line(js: dict) -> str:
    return f"v_L {js['amplitude']['v_L']:.6e} m, N1 {js['peak']['N1']:.4f} N"


def reduced(repeats: int) -> None:
    out = tempfile.mkdtemp()
    command = {m: ["transient", "--model", m, "--out", out] for m in ("shell-reduced", "fe-reduced")}
    side_by_side("transient, Fig. 8 case, 100 periods, bases built", alternated(command, repeats),
                 "shell-reduced", "fe-reduced", 2.0, transient_line)


def full(repeats: int) -> None:
    out = tempfile.mkdtemp()
    command = {"shell": ["transient", "--model", "shell", "--out", out],
               "fe": ["transient", "--model", "fe", "--out", out, *FIG8_SOLID]}
    for m in command:                          # meshes and caches made once, on one period
        whole_process([*command[m], "--set", "time.periods=1"], ranks=2)
    runs = {m: [] for m in command}
    for _ in range(repeats):
        for m in command:
            runs[m].append(whole_process(command[m], ranks=2))
    side_by_side("transient, Fig. 8 case, 100 periods, mpirun -n 2 (solid: the fig8 scene's 10 mm hexahedra)",
                 runs, "shell", "fe", 60.0, transient_line)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--reduced", action="store_true", help="shell-reduced and fe-reduced, 100 periods")
    p.add_argument("--full", action="store_true", help="shell and fe, 100 periods on 2 ranks (minutes)")
    p.add_argument("--full-repeats", type=int, default=1)
    p.add_argument("--no-modal", action="store_true")
    a = p.parse_args()
    if not a.no_modal:
        modal(a.repeats)
    if a.reduced:
        reduced(a.repeats)
    if a.full:
        full(a.full_repeats)


if __name__ == "__main__":
    main()
