"""Campaigns: every listed scene is checked first, then all run (spread over
worker processes), each into its own folder, and one report links them all.

The study here is a probe, ``comparisons.probe``: it records
which process ran it and can be told to fail, so the campaign's bookkeeping
is tested on its own; test_mpi.py runs a real campaign under mpirun.
"""

import json
import os
import re
import sys
from pathlib import Path

import pytest

from workbench.campaign import load_campaign, run_campaign
from shroud.base.errors import InputError


PROBE = """
import os
import time

from shroud.base.parallel import map_parallel

OPTIONS = {"fail": False}


def _pid(_):
    return os.getpid()


def run(scene, out):
    if scene.options["fail"]:
        raise RuntimeError("told to fail")
    inner = map_parallel(_pid, range(4))          # a sweep inside a campaign item
    time.sleep(0.3)                               # long enough that both workers take a scene
    (out / "curve.png").write_bytes(b"\\x89PNG")
    (out / "values.csv").write_text("rpm,amplitude\\n8500,1e-4\\n")
    (out / "report.md").write_text(
        f"# Probe {scene.title}\\n\\n![curve](curve.png)\\n\\n[values](values.csv)\\n\\n"
        f"## Detail\\n\\nrpm = {scene.params.speed.rpm:g}\\n")
    return {"pid": os.getpid(), "inner_pids": inner, "rpm": scene.params.speed.rpm}
"""


@pytest.fixture
def probe(monkeypatch, tmp_path):
    """The probe study as ``comparisons.probe``, importable by the campaign's worker processes too.

    Workers start fresh (shroud.base.parallel: not forked from this process) with this process's
    sys.path, so the probe lives in a package ``comparisons`` put first on it, whose ``__path__``
    also holds the real studies.
    """
    import comparisons
    real = Path(comparisons.__file__).parent
    shadow = tmp_path / "studies" / "comparisons"
    shadow.mkdir(parents=True)
    (shadow / "__init__.py").write_text(f"__path__.append({str(real)!r})\n"
                                        f"exec(open({str(real / '__init__.py')!r}).read())\n")
    (shadow / "probe.py").write_text(PROBE)
    for name in [m for m in sys.modules if m == "comparisons" or m.startswith("comparisons.")]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.syspath_prepend(str(shadow.parent))
    monkeypatch.setenv("SHROUD_WORKERS", "2")
    for name, rpm in (("first", 8000), ("second", 9000), ("third", 10000)):
        (tmp_path / f"{name}.toml").write_text(
            f'study = "probe"\ntitle = "{name}"\n[speed]\nrpm = {rpm}\n[quick.speed]\nrpm = 100\n')
    return tmp_path


def _campaign(folder: Path, body: str) -> Path:
    path = folder / "camp.toml"
    path.write_text('title = "Probe campaign"\n' + body)
    return path


def test_campaign_runs_every_scene_and_links_them(probe):
    path = _campaign(probe, 'campaign = ["first", "second", "third.toml"]\n'
                            '[overrides]\nsecond = ["speed.rpm=9500"]\n')
    out = probe / "out"
    summary = run_campaign(path, out=out)
    assert summary["status"] == "complete"
    record = json.loads((out / "results.json").read_text())
    assert [s["name"] for s in record["scenes"]] == ["first", "second", "third"]
    assert all(s["status"] == "complete" for s in record["scenes"])
    rpms = [json.loads((out / n / "results.json").read_text())["results"]["rpm"]
            for n in ("first", "second", "third")]
    assert rpms == [8000, 9500, 10000]            # the per-scene override reached its scene only
    report = (out / "report.md").read_text()
    targets = re.findall(r"\]\(([^)#]+)\)", report)
    assert {"first/curve.png", "second/values.csv", "third/report.md"} <= set(targets)
    assert all((out / t).exists() for t in targets), "a link of the campaign report is dangling"
    assert "#### Detail" not in report and "### Detail" in report   # nested one level, not two


def test_scenes_spread_over_processes_without_nested_pools(probe):
    path = _campaign(probe, 'campaign = ["first", "second", "third"]\n')
    out = probe / "out"
    run_campaign(path, out=out)
    results = [json.loads((out / n / "results.json").read_text())["results"] for n in ("first", "second", "third")]
    pids = {r["pid"] for r in results}
    assert os.getpid() not in pids and len(pids) == 2      # two workers, none of them this process
    for r in results:                                      # a map inside a campaign item stays in that item
        assert set(r["inner_pids"]) == {r["pid"]}


def test_one_failing_scene_does_not_stop_the_others(probe):
    path = _campaign(probe, 'campaign = ["first", "second", "third"]\n'
                            '[overrides]\nsecond = ["options.fail=true"]\n')
    out = probe / "out"
    summary = run_campaign(path, out=out)
    assert summary["status"] == "complete with failures"
    status = {s["name"]: s["status"] for s in json.loads((out / "results.json").read_text())["scenes"]}
    assert status["first"] == status["third"] == "complete"
    assert status["second"].startswith("failed (RuntimeError: told to fail)")
    assert "told to fail" in (out / "second" / "error.txt").read_text()
    assert "failed (RuntimeError" in (out / "report.md").read_text()


def test_a_failed_scene_makes_the_command_exit_1(probe, capsys):
    from workbench.cli import EXIT_RUN_FAILED, main
    path = _campaign(probe, 'campaign = ["first", "second"]\n[overrides]\nsecond = ["options.fail=true"]\n')
    assert main(["run", str(path), "--out", str(probe / "out")]) == EXIT_RUN_FAILED
    assert "a scene failed" in capsys.readouterr().out
    path = _campaign(probe, 'campaign = ["first", "third"]\n')
    assert main(["run", str(path), "--out", str(probe / "ok")]) == 0


def test_quick_flag_and_command_line_sets_reach_every_scene(probe):
    path = _campaign(probe, 'campaign = ["first", "second"]\nquick = true\n')
    campaign = load_campaign(path, overrides=["load.F0=75"])
    assert campaign.quick
    for entry in campaign.entries:
        assert "load.F0=75" in entry.overrides
    out = probe / "out"
    run_campaign(path, out=out, overrides=["load.F0=75"])
    for name in ("first", "second"):
        record = json.loads((out / name / "results.json").read_text())
        assert record["quick"] and record["results"]["rpm"] == 100
        assert record["parameters"]["load"]["F0"] == 75


def test_a_bad_scene_anywhere_stops_the_campaign_before_it_starts(probe):
    (probe / "second.toml").write_text('study = "probe"\n[options]\nfail = "sometimes"\n')
    path = _campaign(probe, 'campaign = ["first", "second"]\n')
    with pytest.raises(InputError) as err:
        run_campaign(path, out=probe / "out")
    assert err.value.key == "second: options.fail"
    assert not (probe / "out").exists()
