"""Cost of the shell model against the solid, side by side (issue 25's goals).

1. Modal whole process, ``shroud modal --model M --rpm 8500 --modes 5``
   (fresh processes, meshes and caches on disk as a user has them after a
   first run), shell and solid alternated ``--repeats`` times: median wall
   time and peak resident memory of each, their ratio, and the first five
   frequencies of each against the solid's (goal for the shell: < 2 s,
   < 1 GB; the solid's: 3.5 s, 0.7 GB).
2. ``--transient``: ``shroud transient --model shell-reduced`` (100 periods
   of the Fig. 8 case, basis built in the cache beforehand) and, with
   ``--full``, ``--model shell`` (goal: < 60 s on 2 ranks; the solid's 247 s).

    python benchmarks/bench_shell.py
    python benchmarks/bench_shell.py --repeats 5 --transient --full
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

SHROUD = str(Path(sys.executable).with_name("shroud"))


def whole_process(args: list[str]) -> tuple[float, float, dict]:
    """(wall s, peak RSS of the process GB, its JSON) of one ``shroud`` command."""
    t0 = time.perf_counter()
    r = subprocess.run(["/usr/bin/time", "-f", "%M", SHROUD, *args, "--json"], capture_output=True, text=True,
                       env=dict(os.environ, OMP_NUM_THREADS="1"))
    wall = time.perf_counter() - t0
    if r.returncode != 0:
        raise SystemExit(r.stderr)
    rss_kb = float(r.stderr.strip().splitlines()[-1])
    return wall, rss_kb / 1e6, json.loads(r.stdout)


def modal(repeats: int) -> None:
    command = {m: ["modal", "--model", m, "--rpm", "8500", "--modes", "5"] for m in ("shell", "fe")}
    for m in command:                          # meshes, forms' JIT and caches made once, not timed
        whole_process(command[m])
    runs = {m: [] for m in command}
    for _ in range(repeats):
        for m in command:
            runs[m].append(whole_process(command[m]))
    median = {m: (statistics.median(r[0] for r in runs[m]), max(r[1] for r in runs[m])) for m in runs}
    f = {m: {x["label"]: x["f_hz"] for x in runs[m][0][2]["modes"]} for m in runs}
    print(f"modal, 8500 r/min, 5 modes, {repeats} alternated runs, load {os.getloadavg()[0]:.1f}")
    for m in runs:
        print(f"  {m:6s} {runs[m][0][2]['dofs']:6d} DOF  {median[m][0]:6.2f} s  {median[m][1]:5.2f} GB  "
              + "  ".join(f"{k} {v:.1f}" for k, v in f[m].items()))
    print(f"  ratio solid / shell: time {median['fe'][0] / median['shell'][0]:.2f}, "
          f"memory {median['fe'][1] / median['shell'][1]:.2f}")
    print("  shell against solid: " + ", ".join(f"{k} {100 * (f['shell'][k] / f['fe'][k] - 1):+.2f} %"
                                             for k in f["fe"] if k in f["shell"]))


def transient(full: bool) -> None:
    out = Path(tempfile.mkdtemp())
    models = ["shell-reduced"] + (["shell"] if full else [])
    whole_process(["transient", "--model", "shell-reduced", "--out", str(out), "--set", "time.periods=1"])
    for m in models:
        wall, rss, js = whole_process(["transient", "--model", m, "--out", str(out)])
        print(f"transient {m}: {js['dofs']} DOF, 100 periods: run {js['elapsed_s']:.2f} s, whole process "
              f"{wall:.2f} s, {rss:.2f} GB, v_L {js['amplitude']['v_L']:.6e} m, N1 {js['peak']['N1']:.4f} N")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--transient", action="store_true")
    p.add_argument("--full", action="store_true", help="with --transient: the full shell too (minutes)")
    a = p.parse_args()
    modal(a.repeats)
    if a.transient:
        transient(a.full)


if __name__ == "__main__":
    main()
