"""The full-scene records the quick-against-full tests hold: whole, unedited, current, and made again alike.

A record (workbench.records) names the clean commit that made it and the SHA-256 of each file its
study's conclusions depend on directly; ``shroud record SCENE`` makes it again.
"""

import json
import shutil
import subprocess
import sys

import pytest

from workbench import records


@pytest.mark.parametrize("scene", records.RECORDED)
def test_every_record_is_current(scene):
    path = records.RECORDS / f"{scene}.json"
    assert path.is_file(), f"no record of {scene}: run `shroud record {scene}` on a clean tree"
    problems = records.check(records.load(scene)).problems
    assert not problems, f"record of {scene}: {'; '.join(problems)}; run `shroud record {scene}` on a clean tree"


def _fresh_record(scene="stability"):
    """A record as `shroud record` writes it, of the current sources (the conclusions made up)."""
    rec = {"scene": scene, "study": records.study_of(scene), "command": f"shroud run scenes/{scene}.toml",
           "commit": "0123456789abcdef0123456789abcdef01234567",
           "sources": records.file_hashes(records.sources_of(scene)),
           "physics": records.file_hashes(records.physics_of(scene)), "conclusions": {"implicit_bounded": True}}
    rec["digest"] = records.digest(rec)
    return rec


def test_a_fresh_record_is_current():
    rec = _fresh_record()
    assert records.check(rec).current and records.physics_changes(rec) == ()


def test_a_record_made_before_records_carried_physics_stays_current_and_says_so():
    rec = _fresh_record()
    del rec["physics"]
    rec["digest"] = records.digest(rec)
    assert records.check(rec).current and records.physics_changes(rec) is None


def test_a_physics_change_leaves_a_record_current_but_behind():
    rec = _fresh_record()
    rec["physics"]["shroud/core/newmark.py"] = "0" * 64     # made when the integrator read otherwise
    rec["digest"] = records.digest(rec)
    assert records.check(rec).current
    assert records.physics_changes(rec) == ("shroud/core/newmark.py",)
    rec["physics"].pop("shroud/core/contact.py")             # and when the study did not reach the contact law
    rec["digest"] = records.digest(rec)
    assert records.physics_changes(rec) == ("shroud/core/contact.py", "shroud/core/newmark.py")
    rec["physics"]["shroud/core/contact.py"] = "1" * 64
    assert any("digest" in p for p in records.check(rec).problems)     # the physics is part of what it asserts


def test_the_physics_follows_imports_to_the_models_the_registry_loads():
    """stability integrates the beam (reduced_model, reached through the registry's entry points and lazy
    loaders) with Newmark; table1 also takes the solid's modes (reference_fe) and the mesh (meshes)."""
    stability, table1 = records.physics_of("stability"), records.physics_of("table1")
    assert {"shroud/core/newmark.py", "shroud/core/contact.py", "reduced_model/system.py"} <= set(stability)
    assert {"reference_fe/modal.py", "meshes/blade.py", "shroud/params.py"} <= set(table1)
    assert not set(stability) & set(records.sources_of("stability"))     # a source is no physics of its own
    assert not any(p.startswith("shroud/base/") for p in stability + table1)   # logging, cache: no physics


def test_record_check_warns_of_a_record_a_physics_change_left_behind(tmp_path, monkeypatch, capsys):
    from workbench.cli import main
    behind = _fresh_record()
    behind["physics"]["shroud/core/newmark.py"] = "0" * 64
    behind["digest"] = records.digest(behind)
    (tmp_path / "stability.json").write_text(json.dumps(behind))
    monkeypatch.setattr(records, "RECORDS", tmp_path)
    assert main(["record", "--check", "stability"]) == 0                  # a warning, not a failure
    out = capsys.readouterr().out
    assert "stability: current; physics changed since: shroud/core/newmark.py" in out
    assert "warning:" in out and "shroud record stability" in out
    behind["sources"]["comparisons/stability.py"] = "0" * 64               # a study source changed: stale
    behind["digest"] = records.digest(behind)
    (tmp_path / "stability.json").write_text(json.dumps(behind))
    assert main(["record", "--check", "stability"]) == 3


def test_record_stale_makes_again_the_records_a_physics_change_left_behind(tmp_path, monkeypatch):
    """`shroud record --stale` takes what `--check` warns of: a physics change stales no record's sources,
    but its conclusions may no longer be what the code gives."""
    fresh, behind = _fresh_record(), _fresh_record()
    behind["physics"]["shroud/core/newmark.py"] = "0" * 64
    behind["digest"] = records.digest(behind)
    for rec, name in ((fresh, "stability"), (behind, "fig3")):
        rec["scene"] = name
        rec["digest"] = records.digest(rec)
        (tmp_path / f"{name}.json").write_text(json.dumps(rec))
    sources, physics = list(fresh["sources"]), list(fresh["physics"])
    monkeypatch.setattr(records, "RECORDS", tmp_path)
    monkeypatch.setattr(records, "sources_of", lambda scene: sources)      # fig3 as stability's study
    monkeypatch.setattr(records, "physics_of", lambda scene: physics)
    assert records.check(behind).current and not records.due("stability")
    assert records.due("fig3") and records.due("table1")            # behind; and one with no record at all


def test_record_check_counts_the_verdicts_left_undecided(tmp_path, monkeypatch, capsys):
    """Issue 33: a record says how many of its verdicts stay not decided, those of run times apart, and
    flags more than 10 %: here 3 of 5 nested verdicts, one of them a run time."""
    from shroud.core.verdict import TIME_RATIO, Verdict
    from workbench.cli import main
    yes, open_ = Verdict.of(0.5, 1.0, 0.1, True, False, "r").to_json(), Verdict.of(1.0, 1.0, 0.1, True, False, "r")
    cost = Verdict.of(1.0, 1.0, 0.1, "cheaper", "costlier", "timing", unit=TIME_RATIO).to_json()
    rec = _fresh_record()
    rec["conclusions"] = {"a": yes, "b": {"c": [open_.to_json(), yes]}, "d": open_.to_json(), "e": cost, "f": 1.0}
    rec["digest"] = records.digest(rec)
    assert records.decided(rec["conclusions"]) == records.Decided(5, 3, 1)
    (tmp_path / "stability.json").write_text(json.dumps(rec))
    monkeypatch.setattr(records, "RECORDS", tmp_path)
    assert main(["record", "--check", "stability"]) == 0
    assert "5 verdicts, 3 not decided, 1 of them run time or memory, over 10%" in capsys.readouterr().out


def test_a_record_edited_by_hand_is_refused():
    rec = _fresh_record()
    rec["conclusions"]["implicit_bounded"] = False
    assert any("digest" in p for p in records.check(rec).problems)


def test_a_record_older_than_its_study_sources_is_refused():
    rec = _fresh_record()
    source = "comparisons/stability.py"
    rec["sources"][source] = "0" * 64                  # made when the study module read otherwise
    rec["digest"] = records.digest(rec)
    assert any(source in p and "changed" in p for p in records.check(rec).problems)


def test_a_record_from_a_tree_with_changes_is_refused():
    rec = _fresh_record()
    rec["commit"] = "bb14573+local changes"
    rec["digest"] = records.digest(rec)
    assert any("clean git revision" in p for p in records.check(rec).problems)


def test_the_sources_follow_the_study_helpers_it_imports():
    sources = records.sources_of("fig8")
    assert sources[0] == "scenes/fig8.toml" and "comparisons/fig8.py" in sources
    assert any(s.startswith("comparisons/_") for s in sources)        # its private helpers are named too
    # the helpers public in the analysis layer: fig8 imports agreement (`from ... import`), fig4 coexistence
    # (`from shroud.analysis import coexistence`), default agreement through the fig8 study it runs
    assert "shroud/analysis/agreement.py" in sources
    assert "shroud/analysis/coexistence.py" in records.sources_of("fig4")
    assert "shroud/analysis/agreement.py" in records.sources_of("default")
    # a study importing neither names neither, nor any other analysis module (physics below the studies)
    assert not any(s.startswith("shroud/") for s in records.sources_of("table1"))


@pytest.mark.slow
def test_a_record_is_made_again_alike_from_a_clean_clone(tmp_path):
    """`shroud record stability` in a fresh clone of HEAD gives back the committed record (timings aside):
    its conclusions and sources alike. The physics' hashes are left out: a physics change below the study
    since the record was made is a warning of `shroud record --check`, not a stale record, and what this
    test catches is whether it moved the conclusions."""
    if subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], cwd=records.ROOT,
                      capture_output=True, text=True).stdout.strip():
        pytest.skip("the work tree has uncommitted changes: a clone of HEAD would not hold them")
    clone = tmp_path / "clone"
    subprocess.run(["git", "clone", "-q", str(records.ROOT), str(clone)], check=True)
    shared = records.ROOT.parent / "shared"
    if shared.is_dir() and not (tmp_path / "shared").exists():
        shutil.copytree(shared, tmp_path / "shared")
    proc = subprocess.run([sys.executable, "-c", "import sys; sys.path.insert(0, sys.argv[1]); "
                           "from workbench import records; records.record(['stability'])", str(clone)],
                          cwd=clone, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr[-2000:]
    again = json.loads((clone / "tests" / "data" / "records" / "stability.json").read_text())
    committed = records.load("stability")
    for key in records.TIMINGS + ("commit", "digest"):
        again.pop(key), committed.pop(key)
    again.pop("physics"), committed.pop("physics", None)
    assert again == committed
