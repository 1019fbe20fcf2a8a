"""The full-scene records the quick-against-full tests hold: whole, unedited, current, and made again alike.

A record (workbench.records) names the clean commit that made it and the SHA-256 of each file its
study's conclusions depend on directly; ``shroud record SCENE`` makes it again.
"""

import copy
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
           "sources": records.file_hashes(records.sources_of(scene)), "conclusions": {"implicit_bounded": True}}
    rec["digest"] = records.digest(rec)
    return rec


def test_a_fresh_record_is_current():
    assert records.check(_fresh_record()).current


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
    """`shroud record stability` in a fresh clone of HEAD gives back the committed record (timings aside)."""
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
    assert again == committed
