"""Gates and baseline comparison as CI runs them: through the command.

``shroud run`` with a ``[gates]`` table or ``--gate``, ``shroud compare``, and
a campaign with gates, on the beam's natural frequencies (a fraction of a
second per run). The bounds are set from independent values: the paper's
Table 1 gives the first flap mode at 8500 r/min as 284.2 Hz (its beam, N = 6)
and 282.4 Hz (ANSYS); a gate of [281, 286] Hz holds, one of 200 Hz does not.
The paper's beam (reduced.torsion = false) has no torsion field, so it has no
torsion1 mode: a gate on it names a path that is not in the results.
"""

import json
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from workbench import gates
from workbench.cli import main
from shroud.core.verdict import MEMORY_MB, MEMORY_RATIO, TIME_RATIO, RatioVerdict, Verdict, cost, timing, with_rounding

FLAP1 = "results.modal.rows.flap1.reduced"
BEAM = 'study = "default"\ntitle = "beam frequencies"\n' \
       '[options]\nmodal_models = ["reduced"]\ntransient_models = []\n'


def shroud(*argv) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "workbench.cli", *map(str, argv)],
                          capture_output=True, text=True, timeout=300)


def scene(folder: Path, gates: str = "", name: str = "beam.toml") -> Path:
    path = folder / name
    path.write_text(BEAM + (f"[gates]\n{gates}" if gates else ""))
    return path


# The elements and attributes of junit-10.xsd (Jenkins xUnit plugin; pytest's --junitxml
# follows it too): (required, allowed) attributes and allowed children of each element.
JUNIT_10 = {
    "testsuites": (set(), {"name", "time", "tests", "failures", "errors"}, {"testsuite"}),
    "testsuite": ({"name", "tests", "failures", "errors"},
                  {"group", "time", "skipped", "timestamp", "hostname", "id", "package", "file", "log", "url"},
                  {"testsuite", "properties", "testcase", "system-out", "system-err"}),
    "testcase": ({"name"}, {"time", "classname", "group"},
                 {"skipped", "error", "failure", "system-out", "system-err"}),
    "failure": (set(), {"type", "message"}, set()),
    "system-out": (set(), set(), set()),
}


def junit_cases(path: Path) -> list[ET.Element]:
    """The test cases of a JUnit file, after checking it against junit-10.xsd and its own counts."""
    root = ET.parse(path).getroot()
    assert root.tag == "testsuites"
    for element in root.iter():
        required, optional, children = JUNIT_10[element.tag]
        assert required <= set(element.attrib) <= required | optional, (element.tag, element.attrib)
        assert {child.tag for child in element} <= children, element.tag
    cases = root.findall("testsuite/testcase")
    assert int(root.get("tests")) == len(cases)
    assert int(root.get("failures")) == sum(c.find("failure") is not None for c in cases)
    for suite in root.findall("testsuite"):
        assert int(suite.get("tests")) == len(suite.findall("testcase"))
        assert int(suite.get("failures")) == len(suite.findall("testcase/failure"))
    return cases


# --- gates of one scene --------------------------------------------------------

def test_a_held_gate_exits_0_with_one_passing_testcase(tmp_path):
    out = tmp_path / "out"
    proc = shroud("run", scene(tmp_path, f'"{FLAP1}" = {{ min = 281.0, max = 286.0 }}\n'), "--out", out)
    assert proc.returncode == 0, proc.stderr
    [case] = junit_cases(out / "junit.xml")
    assert case.get("name") == FLAP1 and case.find("failure") is None
    [record] = json.loads((out / "results.json").read_text())["gates"]
    assert record["passed"] and 281 <= record["value"] <= 286
    assert record["margin"] == pytest.approx(min(286 - record["value"], record["value"] - 281))
    report = (out / "report.md").read_text()
    assert report.startswith("# beam frequencies\n\n## Gates: 1 of 1 held")


def test_a_broken_gate_exits_3_and_names_value_and_bound(tmp_path):
    out = tmp_path / "out"
    proc = shroud("run", scene(tmp_path, f'"{FLAP1}" = {{ max = 200.0 }}\n'), "--out", out)
    assert proc.returncode == 3, proc.stderr
    [case] = junit_cases(out / "junit.xml")
    [record] = json.loads((out / "results.json").read_text())["gates"]
    assert not record["passed"] and record["margin"] == pytest.approx(200 - record["value"])
    assert record["margin"] < 0
    message = case.find("failure").get("message")
    shown = float(re.match(r"\s*([0-9.eE+-]+)", message).group(1))
    assert shown == pytest.approx(record["value"], rel=1e-5) and "max 200" in message
    assert "FAILED" in proc.stdout and FLAP1 in proc.stdout
    assert "**FAILED**" in (out / "report.md").read_text().split("## Natural")[0]


def test_a_path_not_in_the_results_is_a_failed_gate_that_says_so(tmp_path):
    out = tmp_path / "out"
    proc = shroud("run", scene(tmp_path, '"results.modal.rows.torsion1.reduced" = { max = 1e4 }\n'),
                  "--out", out)
    assert proc.returncode == 3
    [case] = junit_cases(out / "junit.xml")
    message = case.find("failure").get("message")
    assert message.startswith("missing:") and "torsion1" in message and "flap1" in message


def test_command_line_gates_add_to_and_replace_the_scenes_bounds(tmp_path):
    """--gate replaces the scene's max and keeps its min; another --gate adds a path."""
    out = tmp_path / "out"
    path = scene(tmp_path, f'"{FLAP1}" = {{ min = 281.0, max = 286.0 }}\n')
    proc = shroud("run", path, "--out", out, "--gate", f"{FLAP1}<=282",
                  "--gate", "results.modal.rows.chord1.reduced >= 1000", "--json")
    assert proc.returncode == 3
    summary = json.loads(proc.stdout)
    flap1, chord1 = summary["gates"]
    assert (flap1["min"], flap1["max"], flap1["passed"]) == (281.0, 282.0, False)    # 282.4 Hz
    assert chord1["path"] == "results.modal.rows.chord1.reduced" and chord1["passed"]
    assert len(junit_cases(out / "junit.xml")) == 2


def test_a_relative_gate_holds_the_difference_to_another_number(tmp_path):
    """|f_flap1 / f_paper - 1| with the paper's beam value (284.2 Hz) beside ours in results.json."""
    out = tmp_path / "out"
    paper = "results.modal.rows.flap1.paper beam N=6"
    proc = shroud("run", scene(tmp_path, f'"{FLAP1}" = {{ max = 0.02, relative_to = "{paper}" }}\n'
                                         f'"results.modal.rows.flap2.reduced" = {{ max = 1e-4, '
                                         f'relative_to = "results.modal.rows.flap2.paper beam N=6" }}\n'),
                  "--out", out)
    assert proc.returncode == 3
    record = json.loads((out / "results.json").read_text())
    held, broken = record["gates"]
    flap1 = record["results"]["modal"]["rows"][0]
    assert flap1["label"] == "flap1"
    assert held["passed"] and held["value"] == pytest.approx(abs(flap1["reduced"] / 284.2 - 1))
    assert not broken["passed"] and broken["value"] > 1e-4


# --- baseline comparison -------------------------------------------------------

@pytest.fixture(scope="module")
def two_runs(tmp_path_factory):
    folder = tmp_path_factory.mktemp("runs")
    path = scene(folder)
    for name in ("base", "new"):
        assert shroud("run", path, "--out", folder / name).returncode == 0
    return folder


def test_compare_of_two_identical_runs_is_0(two_runs):
    proc = shroud("compare", two_runs / "base", two_runs / "new", "--junit", two_runs / "cmp.xml")
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "All within tolerance" in proc.stdout
    cases = junit_cases(two_runs / "cmp.xml")
    assert cases and all(c.find("failure") is None for c in cases)
    assert not any(c.get("name").endswith("elapsed_s") for c in cases)     # timings are not held


def _drifted_copy(two_runs: Path, name: str, edit) -> Path:
    copy = two_runs / name
    shutil.copytree(two_runs / "new", copy)
    record = json.loads((copy / "results.json").read_text())
    edit(record["results"]["modal"]["rows"])
    (copy / "results.json").write_text(json.dumps(record))
    return copy


def test_a_number_drifted_by_one_percent_is_listed_first_and_exits_3(two_runs):
    def edit(rows):
        rows[2]["reduced"] *= 1.01           # flap2 by 1 %
        rows[0]["reduced"] *= 1.001          # flap1 by 0.1 %
    copy = _drifted_copy(two_runs, "drifted", edit)
    proc = shroud("compare", two_runs / "base", copy, "--json")
    assert proc.returncode == 3
    drifted = json.loads(proc.stdout)["drifted"]
    assert [d["path"] for d in drifted] == ["results.modal.rows.flap2.reduced", "results.modal.rows.flap1.reduced"]
    assert drifted[0]["relative_change"] == pytest.approx(0.01, rel=1e-9)
    table = shroud("compare", two_runs / "base", copy).stdout
    first_row = next(line for line in table.splitlines() if line.startswith("| `"))
    assert "flap2.reduced" in first_row
    # a tolerance above the drift, or ignoring the mode rows, accepts it
    assert shroud("compare", two_runs / "base", copy, "--rtol", "0.02").returncode == 0
    assert shroud("compare", two_runs / "base", copy, "--ignore", "results.modal.rows.*").returncode == 0


def test_a_number_missing_from_one_run_is_a_drift(two_runs):
    copy = _drifted_copy(two_runs, "missing", lambda rows: rows[1].pop("reduced"))
    proc = shroud("compare", two_runs / "base", copy, "--json")
    assert proc.returncode == 3
    [drift] = json.loads(proc.stdout)["drifted"]
    assert drift["path"] == "results.modal.rows.chord1.reduced" and drift["note"] == "missing in NEW"


def _with_conclusions(two_runs: Path, name: str, found: dict) -> Path:
    """A copy of the second run whose results carry the conclusions ``found``."""
    copy = two_runs / name
    shutil.copytree(two_runs / "new", copy)
    record = json.loads((copy / "results.json").read_text())
    record["results"]["conclusions"] = found
    (copy / "results.json").write_text(json.dumps(record))
    return copy


def test_a_flipped_verdict_or_word_is_a_drift_that_exits_3_naming_it(two_runs):
    """A verdict that changes side (its number moved across the threshold) is drift, as is a flipped
    yes/no or a changed word; the verdict's own number drifts beside it."""
    def found(value, order):
        v = Verdict.of(value, threshold=0.05, margin=0.01, below="no effect", above="effect", reason="grid")
        return {"no_effect": v.to_json(), "settled": value < 0.05, "state_order": order}
    base = _with_conclusions(two_runs, "verdict_base", found(0.02, "separate > slip > stick"))
    same = _with_conclusions(two_runs, "verdict_same", found(0.02, "separate > slip > stick"))
    flipped = _with_conclusions(two_runs, "verdict_flipped", found(0.09, "separate > stick > slip"))
    assert shroud("compare", base, same).returncode == 0
    proc = shroud("compare", base, flipped, "--json")
    assert proc.returncode == 3
    drifted = {d["path"]: (d["base"], d["new"]) for d in json.loads(proc.stdout)["drifted"]}
    assert drifted["results.conclusions.no_effect.answer"] == ("no effect", "effect")
    assert drifted["results.conclusions.settled"] == (True, False)
    assert drifted["results.conclusions.state_order"] == ("separate > slip > stick", "separate > stick > slip")
    assert "results.conclusions.no_effect.value" in drifted
    assert "no_effect.answer" in shroud("compare", base, flipped).stdout


def test_a_run_made_before_verdicts_wrote_their_kind_compares_with_one_after(two_runs):
    """A ratio recorded before verdicts wrote their kind is told by its unit and held as "ratio"; a
    difference recorded then (written alike with a band) leaves its kind uncompared, not a drift; a kind
    that changed between two runs that both wrote it is a drift."""
    from workbench.compare import compare
    ratio = RatioVerdict(2.0, 1.0, factor=1.5, noise=1.1, above="more", below="less", between="same", reason="")
    difference = Verdict.of(0.02, threshold=0.05, margin=0.01, below=True, above=False, reason="")
    now = {"ratio": ratio.to_json(), "difference": difference.to_json()}
    before = {k: {key: v for key, v in record.items() if key != "kind"} for k, record in now.items()}
    old, new = _with_conclusions(two_runs, "kindless", before), _with_conclusions(two_runs, "kinds", now)
    comparison = compare(old, new)
    assert not comparison.drifts and "results.conclusions.ratio.kind" in comparison.compared
    assert "results.conclusions.difference.kind" not in comparison.compared
    relabelled = _with_conclusions(two_runs, "relabelled", {**now, "ratio": {**now["ratio"], "kind": "band"}})
    assert [d.path for d in compare(old, relabelled).drifts] == ["results.conclusions.ratio.kind"]
    assert [d.path for d in compare(new, relabelled).drifts] == ["results.conclusions.ratio.kind"]


def test_run_times_are_skipped_by_what_they_are(two_runs):
    """Keys ending in _s (and everything under them), _time_ratio keys, and values whose unit declares
    them drawn from run times (verdicts, a fit of run times as convergence's cost_growth.*.time_slope)
    differ between identical runs and are never drift; the same change to a physical number is, also
    to one beside them with a unit of its own."""
    def found(scale):
        verdict = RatioVerdict(scale * 1.0, 10.0, factor=3.0, noise=2.0, above="costlier", below="cheaper",
                               between="comparable", reason="timing noise", unit=TIME_RATIO)
        return {"cost": verdict.to_json(), "solve_s": {"4": scale * 0.003}, "reduced_to_full_time_ratio": scale,
                "cost_growth": {"hex": {"time_slope": timing(1.8 * scale), "memory_slope": 1.2 * scale}},
                "gap": {"value": scale * 1e-4, "unit": "m"}, "time_step": scale * 1e-5}
    base = _with_conclusions(two_runs, "timed_base", found(1.0))
    slower = _with_conclusions(two_runs, "timed_slower", found(5.0))
    proc = shroud("compare", base, slower, "--json")
    assert proc.returncode == 3
    assert sorted(d["path"] for d in json.loads(proc.stdout)["drifted"]) == [
        "results.conclusions.cost_growth.hex.memory_slope", "results.conclusions.gap.value",
        "results.conclusions.time_step"]


def test_a_declared_memory_is_skipped_and_named_while_an_undeclared_number_beside_it_drifts(two_runs):
    """Memory a run allocated is a cost the rank count sets, as run time is one the machine sets (MUMPS's
    factor of convergence's 3.5 mm tetrahedra: 87.8 MB serially, 89.3 MB on 2 ranks, 89.8 MB on 3): a
    value declared so (shroud.core.verdict.cost, units MEMORY_MB and MEMORY_RATIO) is skipped by what it
    is and counted as memory in compare's output; the same 2 % move of the mesh's DOF count beside it,
    and of a memory size that declares nothing (named like one: factor_MB), drifts."""
    def found(memory=1.0, dofs=1.0, undeclared=1.0):
        return {"meshes": [{"dofs": 45204 * dofs, "factor_MB": cost(87.8 * memory, MEMORY_MB)}],
                "cost_growth": {"tet": {"memory_slope": cost(1.43 * memory, MEMORY_RATIO)}},
                "factor_MB": 87.8 * undeclared}
    base = _with_conclusions(two_runs, "memory_base", found())
    more = _with_conclusions(two_runs, "memory_more", found(memory=1.02))
    beside = _with_conclusions(two_runs, "memory_beside", found(memory=1.02, dofs=1.02))
    named = _with_conclusions(two_runs, "memory_named", found(undeclared=1.02))

    proc = shroud("compare", base, more, "--json")
    assert proc.returncode == 0, proc.stdout
    assert json.loads(proc.stdout)["skipped"]["memory"] == 2
    assert "memory" in shroud("compare", base, more).stdout
    proc = shroud("compare", base, beside, "--json")
    assert proc.returncode == 3
    assert [d["path"] for d in json.loads(proc.stdout)["drifted"]] == ["results.conclusions.meshes.0.dofs"]
    proc = shroud("compare", base, named, "--json")
    assert proc.returncode == 3
    assert [d["path"] for d in json.loads(proc.stdout)["drifted"]] == ["results.conclusions.factor_MB"]


def test_a_declared_rounding_holds_its_numbers_to_their_spread_and_no_others(two_runs):
    """A study declares the round-off of some numbers (with_rounding; e.g. MacNeal-Harder's thin beam, whose
    tip deflection MUMPS's ordering moves by up to 6.3e-5): compare holds them to the declared spread instead
    of rtol 1e-6 and says so; a move beyond it drifts, named with its spread; the same move of a number beside
    them that declares nothing drifts; a verdict's answer is held for equality whatever its rounding."""
    spread = 1e-4                                   # relative, of the tip deflection

    def found(tip_scale=1.0, beside_scale=1.0, threshold=0.015):
        tip, published = 5.2208e-3 * tip_scale, 5.256e-3
        error = tip / published - 1.0
        verdict = Verdict.of(abs(error), threshold=threshold, margin=0.002 + spread, below="within",
                             above="outside", reason="mesh and round-off")
        row = {"case": "thin", "shell": tip, "error": error,
               "verdict": with_rounding(verdict.to_json(), "orderings", value=spread)}
        return {"thin": with_rounding(row, "orderings", shell=spread * 5.2208e-3, error=spread),
                "thick": 5.42e-3 * beside_scale}
    base = _with_conclusions(two_runs, "rounded_base", found())
    within = _with_conclusions(two_runs, "rounded_within", found(tip_scale=1 + 0.5 * spread))
    beyond = _with_conclusions(two_runs, "rounded_beyond", found(tip_scale=1 + 3 * spread))
    beside = _with_conclusions(two_runs, "rounded_beside", found(beside_scale=1 + 0.5 * spread))
    flipped = _with_conclusions(two_runs, "rounded_flipped", found(threshold=0.004))

    proc = shroud("compare", base, within, "--json")
    assert proc.returncode == 0, proc.stdout
    rounded = json.loads(proc.stdout)["rounded"]
    assert rounded["results.conclusions.thin.shell"] == pytest.approx(spread * 5.2208e-3)
    assert rounded["results.conclusions.thin.verdict.value"] == spread
    assert "results.conclusions.thick" not in rounded
    assert "held to the rounding their study declares" in shroud("compare", base, within).stdout

    proc = shroud("compare", base, beyond, "--json")
    assert proc.returncode == 3
    drifted = {d["path"]: d["note"] for d in json.loads(proc.stdout)["drifted"]}
    assert set(drifted) == {"results.conclusions.thin.shell", "results.conclusions.thin.error",
                            "results.conclusions.thin.verdict.value"}
    assert drifted["results.conclusions.thin.shell"] == "beyond its declared rounding 5.22e-07"

    proc = shroud("compare", base, beside, "--json")
    assert proc.returncode == 3
    assert [d["path"] for d in json.loads(proc.stdout)["drifted"]] == ["results.conclusions.thick"]

    proc = shroud("compare", base, flipped, "--json")
    assert proc.returncode == 3
    assert {d["path"] for d in json.loads(proc.stdout)["drifted"]} >= {"results.conclusions.thin.verdict.answer"}


# --- gates on yes/no and words -------------------------------------------------

def test_a_gate_with_equals_holds_words_and_yes_no(tmp_path):
    """equals holds a word (the study's name) and a yes/no; a wrong word, or a yes/no given as a number,
    is a failed gate that says what was found."""
    path = scene(tmp_path, '"study" = { equals = "default" }\n"quick" = { equals = false }\n')
    out = tmp_path / "out"
    assert shroud("run", path, "--out", out).returncode == 0
    assert [r["passed"] for r in json.loads((out / "results.json").read_text())["gates"]] == [True, True]
    proc = shroud("run", path, "--out", tmp_path / "flipped", "--gate", "study==fig8", "--gate", "quick==0")
    assert proc.returncode == 3
    records = {r["path"]: r for r in json.loads((tmp_path / "flipped" / "results.json").read_text())["gates"]}
    assert not records["study"]["passed"] and "'default', not 'fig8'" in records["study"]["message"]
    assert not records["quick"]["passed"]


def test_a_gate_on_a_verdict_holds_its_answer(tmp_path):
    """A path ending at a verdict record: equals gates its answer, max and min its number; a record
    without a status is never a pass."""
    v = Verdict.of(0.02, threshold=0.05, margin=0.01, below="no effect", above="effect", reason="grid")
    document = {"status": "complete", "results": {"no_effect": v.to_json()}}
    held = gates.hold((gates.from_option("results.no_effect==no effect"),
                       gates.from_option("results.no_effect<=0.03")), document)
    assert [r["passed"] for r in held] == [True, True]
    flipped = {"status": "complete", "results": {"no_effect": Verdict.of(0.09, 0.05, 0.01, "no effect", "effect",
                                                                          "grid").to_json()}}
    [record] = gates.hold((gates.from_option("results.no_effect=='no effect'"),), flipped)
    assert not record["passed"] and record["value"] == "effect"
    [record] = gates.hold((gates.from_option("results.no_effect==no effect"),), {"results": document["results"]})
    assert not record["passed"] and "status: missing" in record["message"]


# --- campaigns -----------------------------------------------------------------

def test_a_campaign_with_one_failing_gate_exits_3(tmp_path):
    scene(tmp_path, f'"{FLAP1}" = {{ min = 281.0, max = 286.0 }}\n', "held.toml")
    scene(tmp_path, "", "broken.toml")
    camp = tmp_path / "camp.toml"
    camp.write_text('title = "gated"\ncampaign = ["held", "broken"]\n'
                    f'[gates.broken]\n"{FLAP1}" = {{ max = 200.0 }}\n')
    out = tmp_path / "out"
    proc = shroud("run", camp, "--out", out, "--gate", "results.modal.rpm>=8500")   # reaches every scene
    assert proc.returncode == 3, proc.stderr
    assert len(junit_cases(out / "junit.xml")) == 4
    root = ET.parse(out / "junit.xml").getroot()
    suites = {s.get("name"): s for s in root.findall("testsuite")}
    assert set(suites) == {"held", "broken"}
    assert suites["held"].get("failures") == "0" and suites["broken"].get("failures") == "1"
    record = json.loads((out / "results.json").read_text())
    assert {s["name"]: s["gates"] for s in record["scenes"]} == {
        "held": {"held": 2, "failed": 0}, "broken": {"held": 1, "failed": 1}}
    summary = (out / "report.md").read_text().split("## held")[0]
    assert "**Gates: 1 failed**" in summary and "| broken | 1 of 2 |" in summary
    # the campaign folders compare scene by scene
    copy = tmp_path / "copy"
    shutil.copytree(out, copy)
    assert shroud("compare", out, copy).returncode == 0
    held = json.loads((copy / "held" / "results.json").read_text())
    held["results"]["modal"]["rpm"] = 8600.0
    (copy / "held" / "results.json").write_text(json.dumps(held))
    proc = shroud("compare", out, copy, "--json")
    assert proc.returncode == 3
    assert [d["path"] for d in json.loads(proc.stdout)["drifted"]] == ["held/results.modal.rpm"]


# --- bad input: one line, exit 2, nothing written ------------------------------

def _refused(capsys, argv: list, key: str, out: Path) -> str:
    code = main([str(a) for a in argv])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2, err
    assert len(err) == 1 and err[0].startswith(f"error: {key}:"), err
    assert not out.exists(), f"{out} was written for bad input"
    return err[0]


@pytest.mark.parametrize("gates, key", [
    (f'"{FLAP1}" = {{ max = "small" }}\n', f"gates.{FLAP1}.max"),
    (f'"{FLAP1}" = {{ max = true }}\n', f"gates.{FLAP1}.max"),
    (f'"{FLAP1}" = {{ maximum = 300.0 }}\n', f"gates.{FLAP1}.maximum"),
    (f'"{FLAP1}" = {{ min = 300.0, max = 200.0 }}\n', f"gates.{FLAP1}"),
    (f'"{FLAP1}" = {{ relative_to = "results.modal.rpm" }}\n', f"gates.{FLAP1}"),
    (f'"{FLAP1}" = {{ max = 1.0, relative_to = 3 }}\n', f"gates.{FLAP1}.relative_to"),
    (f'"{FLAP1}" = 300.0\n', f"gates.{FLAP1}"),
    ('"results..modal" = { max = 1.0 }\n', "gates"),
    ('" results.modal" = { max = 1.0 }\n', "gates"),
])
def test_bad_gate_in_a_scene(tmp_path, capsys, gates, key):
    out = tmp_path / "out"
    _refused(capsys, ["run", scene(tmp_path, gates), "--out", out], key, out)


def test_gates_that_are_not_a_table(tmp_path, capsys):
    path = tmp_path / "beam.toml"
    path.write_text('gates = "strict"\n' + BEAM)
    _refused(capsys, ["run", path, "--out", tmp_path / "out"], "gates", tmp_path / "out")


@pytest.mark.parametrize("option", [
    f"{FLAP1}=300", f"{FLAP1}<300", f"{FLAP1}<=", "<=300", f"{FLAP1}<=abc", f"{FLAP1}<=nan",
    f"{FLAP1}>=inf", "results..modal<=1", f"{FLAP1}<=1<=2",
])
def test_malformed_gate_option(tmp_path, capsys, option):
    out = tmp_path / "out"
    _refused(capsys, ["run", scene(tmp_path), "--out", out, "--gate", option], "--gate", out)


def test_gate_option_contradicting_the_scene(tmp_path, capsys):
    out = tmp_path / "out"
    path = scene(tmp_path, f'"{FLAP1}" = {{ min = 281.0, max = 286.0 }}\n')
    line = _refused(capsys, ["run", path, "--out", out, "--gate", f"{FLAP1}<=200"], f"gates.{FLAP1}", out)
    assert "min 281 is above max 200" in line


def test_bad_campaign_gates_run_nothing(tmp_path, capsys):
    scene(tmp_path, "", "a.toml")
    camp = tmp_path / "camp.toml"
    out = tmp_path / "out"
    camp.write_text('campaign = ["a"]\n[gates.b]\n"results.modal.rpm" = { max = 1.0 }\n')
    _refused(capsys, ["run", camp, "--out", out], "gates.b", out)
    camp.write_text('campaign = ["a"]\n[gates.a]\n"results.modal.rpm" = { most = 1.0 }\n')
    _refused(capsys, ["run", camp, "--out", out], "a: gates.a.results.modal.rpm.most", out)


def test_bad_compare_arguments(tmp_path, capsys):
    empty, run = tmp_path / "empty", tmp_path / "run"
    empty.mkdir()
    run.mkdir()
    (run / "results.json").write_text(json.dumps({"study": "default", "status": "complete", "results": {"x": 1.0}}))
    report = tmp_path / "cmp.xml"
    line = _refused(capsys, ["compare", empty, run, "--junit", report], "BASE", report)
    assert "no results.json" in line
    _refused(capsys, ["compare", run, tmp_path / "nowhere", "--junit", report], "NEW", report)
    _refused(capsys, ["compare", run, run, "--rtol", "-1", "--junit", report], "--rtol", report)
    _refused(capsys, ["compare", run, run, "--junit", empty], "--junit", report)
    (empty / "results.json").write_text("{not json")
    _refused(capsys, ["compare", empty, run, "--junit", report], "BASE", report)
    # a record without a status is refused, never read as complete
    (empty / "results.json").write_text(json.dumps({"study": "default", "results": {"x": 1.0}}))
    assert "has no status" in _refused(capsys, ["compare", run, empty, "--junit", report], "NEW", report)
    # two runs of different studies: said in one line, not as a list of missing numbers
    (empty / "results.json").write_text(json.dumps({"study": "fig3", "status": "complete", "results": {"y": 1}}))
    line = _refused(capsys, ["compare", run, empty, "--junit", report], "NEW", report)
    assert "'default'" in line and "'fig3'" in line
