"""Beyond one process: the same commands under ``mpirun -n 2`` give the serial
answers, independent runs spread over the ranks, and only one rank writes.

MPICH's mpirun comes with the DOLFINx wheel (.venv/bin/mpirun).
"""

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

BIN = Path(sys.executable).parent
MPIRUN = shutil.which("mpirun", path=str(BIN)) or shutil.which("mpirun")
# The coarse solid mesh of the verification gates (2 elements through the thickness).
COARSE = "fe.mesh_size=0.005"          # the default hexahedral solid (28 929 DOF)
pytestmark = [pytest.mark.mpi, pytest.mark.skipif(MPIRUN is None, reason="no mpirun")]


def shroud(argv: list[str], ranks: int = 1, cwd: Path | None = None, timeout: float = 900):
    """Run the shroud command (serially or on ``ranks`` MPI ranks); return stdout, stderr."""
    command = [sys.executable, "-m", "workbench.cli", *argv]
    if ranks > 1:
        command = [MPIRUN, "-n", str(ranks), *command]
    env = {**os.environ, "OMP_NUM_THREADS": "1"}
    proc = subprocess.run(command, capture_output=True, text=True, cwd=cwd, env=env, timeout=timeout)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return proc.stdout, proc.stderr


SPREAD = """
import json, os
from shroud.base.parallel import map_parallel, mpi_rank, mpi_size
def where(i):
    return (i * i, mpi_rank())
out = map_parallel(where, range(5))
if mpi_rank() == 0:
    print(json.dumps({"size": mpi_size(), "out": out}))
"""


def test_map_spreads_items_over_ranks_and_gathers_in_order():
    proc = subprocess.run([MPIRUN, "-n", "2", sys.executable, "-c", SPREAD],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    record = json.loads(proc.stdout)
    assert record["size"] == 2
    assert [v for v, _ in record["out"]] == [0, 1, 4, 9, 16]
    assert [r for _, r in record["out"]] == [0, 1, 0, 1, 0]


def _reduced_scene(folder: Path, name: str, rpm: float) -> Path:
    path = folder / f"{name}.toml"
    path.write_text(f'study = "default"\ntitle = "{name}"\n[speed]\nrpm = {rpm}\n[time]\nperiods = 12\n'
                    '[options]\nmodal_models = ["reduced"]\ntransient_models = ["reduced"]\n')
    return path


def test_scene_under_mpirun_is_written_once_by_rank_0(tmp_path):
    path = _reduced_scene(tmp_path, "one", 10000)
    _, err = shroud(["run", str(path), "--out", str(tmp_path / "out")], ranks=2, cwd=tmp_path)
    record = json.loads((tmp_path / "out" / "results.json").read_text())
    assert record["status"] == "complete" and record["host"]["mpi_ranks"] == 2
    serial_dir = tmp_path / "serial"
    shroud(["run", str(path), "--out", str(serial_dir)], cwd=tmp_path)
    serial = json.loads((serial_dir / "results.json").read_text())
    assert record["results"]["fig8"]["amplitude"] == serial["results"]["fig8"]["amplitude"]
    files = sorted(str(p.relative_to(tmp_path / "out")) for p in (tmp_path / "out").rglob("*"))
    assert files == sorted(str(p.relative_to(serial_dir)) for p in serial_dir.rglob("*"))


def test_campaign_spreads_scenes_over_ranks(tmp_path):
    for name, rpm in (("first", 9000), ("second", 10000)):
        _reduced_scene(tmp_path, name, rpm)
    camp = tmp_path / "camp.toml"
    camp.write_text('title = "two ranks"\ncampaign = ["first", "second"]\n')
    shroud(["run", str(camp), "--out", str(tmp_path / "out")], ranks=2, cwd=tmp_path)
    record = json.loads((tmp_path / "out" / "results.json").read_text())
    assert record["spread"] == "2 MPI ranks" and record["status"] == "complete"
    ranks = [json.loads((tmp_path / "out" / n / "results.json").read_text())["host"]["mpi_rank"]
             for n in ("first", "second")]
    assert ranks == [0, 1]
    assert "[first](#first)" in (tmp_path / "out" / "report.md").read_text()


@pytest.mark.fe
@pytest.mark.slow
def test_fe_modal_on_two_ranks_matches_serial(tmp_path):
    argv = ["modal", "--model", "fe", "--rpm", "8500", "--modes", "4", "--json", "--set", COARSE]
    serial = json.loads(shroud(argv)[0])
    parallel = json.loads(shroud(argv, ranks=2)[0])
    assert [m["label"] for m in parallel["modes"]] == [m["label"] for m in serial["modes"]]
    for a, b in zip(parallel["modes"], serial["modes"]):
        assert a["f_hz"] == pytest.approx(b["f_hz"], rel=1e-7)


@pytest.mark.fe
@pytest.mark.slow
@pytest.mark.parametrize("model", ["fe-reduced", "fe", "shell"])
def test_fe_transient_on_two_ranks_matches_serial(tmp_path, model):
    """The solid's factor and products spread over the ranks; the shell whole on each rank
    (reference_fe.system._on_every_rank): either way the serial answers."""
    argv = ["transient", "--model", model, "--set", "time.periods=2", "--set", COARSE, "--json"]
    # Serial first: it builds (or reuses) the reduction basis, which the ranks then read from the cache.
    serial = json.loads(shroud([*argv, "--out", str(tmp_path / "s")])[0])
    parallel = json.loads(shroud([*argv, "--out", str(tmp_path / "p")], ranks=2)[0])
    assert parallel["dofs"] == serial["dofs"] and parallel["steps"] == serial["steps"]
    for key in ("v_L", "w_L"):
        assert parallel["amplitude"][key] == pytest.approx(serial["amplitude"][key], rel=1e-6)
    for key in ("N1", "N2", "Ff1", "Ff2"):
        assert parallel["peak"][key] == pytest.approx(serial["peak"][key], rel=1e-6, abs=1e-9)


@pytest.mark.fe
@pytest.mark.slow
def test_fig8_scene_with_both_solid_models_on_two_ranks_matches_serial(tmp_path):
    """The whole Fig. 8 study with both solid models (6 periods) under mpirun: the solid models run
    over both ranks, the contact-state maps draw every face facet, and the numbers equal the serial run's."""
    argv = ["run", "scenes/fig8.toml", "--quick", "--set", 'options.models=["fe", "fe-reduced"]',
            "--set", "options.reference=fe", "--set", "time.periods=6", "--set", "options.window_periods=2",
            "--set", "options.plot_periods=1"]
    root = Path(__file__).resolve().parents[1]
    shroud([*argv, "--out", str(tmp_path / "s")], cwd=root)
    shroud([*argv, "--out", str(tmp_path / "p")], ranks=2, cwd=root)
    serial, parallel = (json.loads((tmp_path / d / "results.json").read_text()) for d in ("s", "p"))
    assert parallel["status"] == "complete" and parallel["host"]["mpi_ranks"] == 2
    for model in ("fe", "fe-reduced"):
        for key in ("v_L", "w_L"):
            assert parallel["results"]["amplitude"][model][key] == pytest.approx(
                serial["results"]["amplitude"][model][key], rel=1e-6)
        assert (tmp_path / "p" / f"contact_map_{model}.png").stat().st_size > 10_000
    # The contact elements come in one order whatever the ranks (reference_fe.contact_faces.face_nodes):
    # the maps' shares once differed by up to 0.37 % under mpirun, their weights in the partition's order.
    # The reduced solid runs the same arithmetic on every rank count; the distributed solid's factor
    # rounds differently (amplitudes 1e-11 apart), within shroud compare's default tolerance (1e-6).
    for model, rel in (("fe-reduced", 0.0), ("fe", 1e-6)):
        for side in ("side1", "side2"):
            for state, share in serial["results"]["contact_map"][model][side]["area_weighted_share"].items():
                got = parallel["results"]["contact_map"][model][side]["area_weighted_share"][state]
                assert got == pytest.approx(share, rel=rel, abs=1e-12), (model, side, state)
            for state, share in serial["results"]["state_fraction"][model][side].items():
                assert parallel["results"]["state_fraction"][model][side][state] == pytest.approx(share, rel=rel)


def test_shell_modal_and_static_on_two_ranks_give_the_serial_answers():
    """The shell model (mixed P2/CR space, T-joint mesh) distributed over two ranks."""
    args = ["modal", "--model", "shell", "--rpm", "10000", "--modes", "5", "--json"]
    serial, parallel = (json.loads(shroud(args, ranks=r)[0]) for r in (1, 2))
    for a, b in zip(serial["modes"], parallel["modes"]):
        assert a["label"] == b["label"] and b["f_hz"] == pytest.approx(a["f_hz"], rel=1e-7)
    args = ["static", "--model", "shell", "--tip-force", "0", "100", "0", "--rpm", "10000", "--json"]
    serial, parallel = (json.loads(shroud(args, ranks=r)[0]) for r in (1, 2))
    for key in ("X", "Y", "Z", "v_L", "w_L"):
        assert parallel["tip"][key] == pytest.approx(serial["tip"][key], rel=1e-8, abs=1e-15)


def _shell_scene(folder: Path, name: str, rpm: float) -> Path:
    path = folder / f"{name}.toml"
    path.write_text(f'study = "default"\ntitle = "{name}"\n[speed]\nrpm = {rpm}\n[time]\nperiods = 4\n'
                    '[options]\nmodal_models = ["shell"]\ntransient_models = ["shell-reduced"]\nwindow_periods = 2\n')
    return path


@pytest.mark.fe
def test_shell_campaign_and_sweep_on_two_ranks_give_the_serial_answers(tmp_path):
    """The shell models where the solid's go, under mpirun: a campaign of two scenes with the shell's modes
    and the reduced shell's transient (one scene per rank, each rank's shell on its own communicator), and a
    time-domain sweep of the reduced shell (its speeds spread over the ranks), each equal to its serial run."""
    for name, rpm in (("first", 9000), ("second", 10000)):
        _shell_scene(tmp_path, name, rpm)
    camp = tmp_path / "camp.toml"
    camp.write_text('title = "shell on two ranks"\ncampaign = ["first", "second"]\n')
    shroud(["run", str(camp), "--out", str(tmp_path / "out")], ranks=2, cwd=tmp_path)
    assert json.loads((tmp_path / "out" / "results.json").read_text())["spread"] == "2 MPI ranks"
    for rank, name in enumerate(("first", "second")):
        shroud(["run", str(tmp_path / f"{name}.toml"), "--out", str(tmp_path / name)], cwd=tmp_path)
        spread, serial = (json.loads((d / "results.json").read_text())
                          for d in (tmp_path / "out" / name, tmp_path / name))
        assert spread["status"] == "complete" and spread["host"]["mpi_rank"] == rank
        for a, b in zip(spread["results"]["modal"]["rows"], serial["results"]["modal"]["rows"]):
            assert a["label"] == b["label"] and a["shell"] == pytest.approx(b["shell"], rel=1e-9)
        for key in ("v_L", "w_L"):
            assert spread["results"]["fig8"]["amplitude"]["shell-reduced"][key] == pytest.approx(
                serial["results"]["fig8"]["amplitude"]["shell-reduced"][key], rel=1e-9)
    argv = ["sweep", "--model", "shell-reduced", "--rpm-from", "9500", "--rpm-to", "10500", "--rpm-count", "3",
            "--set", "time.periods=4", "--json"]
    serial = json.loads(shroud(argv)[0])            # first: it builds the reduction basis at each speed
    parallel = json.loads(shroud(argv, ranks=2)[0])
    assert parallel["rpm"] == serial["rpm"] and parallel["dofs"] == serial["dofs"]
    for key in ("amplitude_v_L", "amplitude_w_L"):
        assert parallel[key] == pytest.approx(serial[key], rel=1e-9)


def test_a_mistuning_study_on_two_ranks_streams_every_sample_to_rank_zeros_folder_and_resumes(tmp_path):
    """comparisons/ring_mistuning.py under mpirun -n 2: the samples of both ranks land in the one samples.jsonl
    of the run's folder (the other rank runs in a scratch folder), and a run killed in the middle of a line
    resumes on two ranks with the serial run's statistics."""
    scene = Path(__file__).resolve().parents[1] / "scenes" / "ring_mistuning.toml"
    small = ["ring.blades=4", "time.periods=20", "options.samples=3", "options.rpms=[10000.0]",
             "options.scatters=[0.005, 0.013]", "options.scatter_samples=2", "options.preload_rpms=[12000.0]"]
    sets = [arg for s in small for arg in ("--set", s)]
    serial, spread = tmp_path / "serial", tmp_path / "spread"
    shroud(["run", str(scene), "--quick", "--out", str(serial), *sets])
    shroud(["run", str(scene), "--quick", "--out", str(spread), *sets], ranks=2)
    lines = (spread / "samples.jsonl").read_text().splitlines()
    assert len(lines) == 9                                 # 3 main, 2 unloaded at 0.5 %, 2 x 2 preloaded
    (spread / "samples.jsonl").write_text("\n".join(lines[:4]) + "\n" + lines[4][:25])
    shroud(["run", str(scene), "--quick", "--out", str(spread), *sets], ranks=2)
    results = [json.loads((d / "results.json").read_text())["results"] for d in (serial, spread)]
    assert results[0]["scatter"] == results[1]["scatter"] and results[0]["amplification"] == results[1]["amplification"]
    assert len((spread / "samples.jsonl").read_text().splitlines()) == 9


def test_a_step_file_the_solid_cannot_use_stops_every_rank(tmp_path):
    """Rank 0 reads the file while meshing: its one-line refusal (exit 2) reaches the other rank, which
    would otherwise wait for the mesh for ever."""
    (tmp_path / "empty.step").write_text("")
    command = [MPIRUN, "-n", "2", sys.executable, "-m", "workbench.cli", "modal", "--model", "fe",
               "--set", f"blade.step={tmp_path / 'empty.step'}", "--set", "fe.cell=tet", "--set", "fe.mesh_size=0.0035"]
    env = {**os.environ, "OMP_NUM_THREADS": "1", "SHROUD_CACHE": str(tmp_path / "cache")}
    proc = subprocess.run(command, capture_output=True, text=True, env=env, timeout=120)
    assert proc.returncode == 2, proc.stderr[-2000:]
    assert proc.stderr.strip().splitlines()[-1].startswith("error: blade.step:")
