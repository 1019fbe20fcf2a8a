"""A scene builds only what it needs, and what it builds once it reuses.

Each run happens in a fresh interpreter, as a user's would, so the modules it
loaded and the log it wrote are exactly what that scene caused.
"""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from shroud.base.cache import cached

FE_STACK = {"dolfinx", "dolfinx_solver", "gmsh", "petsc4py", "slepc4py", "ufl", "basix", "meshio",
            "pyvista", "mpi4py"}

PROBE = """
import json, sys
from workbench.cli import main
code = main(sys.argv[1:])
print(json.dumps({"code": code, "modules": sorted(sys.modules)}))
"""


def run_cli(argv, cache: Path) -> tuple[int, set[str], str]:
    """Run ``shroud`` in a fresh interpreter: exit code, modules it loaded, its log."""
    env = {**os.environ, "SHROUD_CACHE": str(cache)}
    proc = subprocess.run([sys.executable, "-c", PROBE, *argv], capture_output=True, text=True, env=env)
    assert proc.returncode == 0, proc.stderr
    record = json.loads(proc.stdout.strip().splitlines()[-1])
    return record["code"], set(record["modules"]), proc.stderr


def scene(tmp_path: Path, options: str, extra: str = "") -> Path:
    path = tmp_path / "scene.toml"
    path.write_text(f'study = "default"\ntitle = "lean"\n[speed]\nrpm = 10000\n[time]\nperiods = 12\n'
                    f"{extra}[options]\n{options}\n")
    return path


def test_reduced_scene_never_loads_the_fe_stack(tmp_path):
    path = scene(tmp_path, 'modal_models = ["reduced"]\ntransient_models = ["reduced", "full"]')
    code, modules, _ = run_cli(["run", str(path), "--out", str(tmp_path / "out")], tmp_path / "cache")
    assert code == 0
    assert not {m.split(".")[0] for m in modules} & FE_STACK
    # the reference_fe package declares its models (reference_fe.models); none of its builders is loaded
    assert not any(m.startswith(("reference_fe.", "meshes")) and m != "reference_fe.models" for m in modules)
    record = json.loads((tmp_path / "out" / "results.json").read_text())
    assert record["status"] == "complete" and "dolfinx" not in record["versions"]


def test_modal_scene_builds_no_contact_and_no_integrator(tmp_path):
    path = scene(tmp_path, 'modal_models = ["reduced"]\ntransient_models = []')
    code, modules, _ = run_cli(["run", str(path), "--out", str(tmp_path / "out")], tmp_path / "cache")
    assert code == 0
    assert "shroud.core.contact" not in modules and "shroud.core.newmark" not in modules
    assert "reduced_model.modal" in modules


def test_cache_key_follows_exactly_the_inputs(tmp_path, monkeypatch):
    """Same inputs reuse the artefact; any changed input builds a new one."""
    monkeypatch.setenv("SHROUD_CACHE", str(tmp_path))
    builds = []

    def build(path: Path) -> None:
        builds.append(path)
        path.write_text("artefact")

    first = cached("probe", {"size": 0.0035, "order": 2}, ".txt", build)
    again = cached("probe", {"order": 2, "size": 0.0035}, ".txt", build)     # key order is irrelevant
    other = cached("probe", {"size": 0.003, "order": 2}, ".txt", build)
    assert first == again != other
    assert len(builds) == 2 and first.read_text() == "artefact"
    assert not list(tmp_path.glob("probe/.*tmp*")), "a temporary build file was left behind"


@pytest.mark.fe
@pytest.mark.slow
def test_second_fe_run_reuses_the_mesh_and_says_so(tmp_path):
    path = scene(tmp_path, 'modal_models = ["fe"]\ntransient_models = []\nn_modes = 2')
    cache = tmp_path / "cache"
    _, modules, first = run_cli(["run", str(path), "--out", str(tmp_path / "a")], cache)
    assert "dolfinx" in modules
    assert "building blade mesh" in first and "reused" not in first
    _, _, second = run_cli(["run", str(path), "--out", str(tmp_path / "b")], cache)
    assert "reused blade mesh" in second and "building" not in second
    f_first = json.loads((tmp_path / "a" / "results.json").read_text())["results"]["modal"]["rows"]
    f_second = json.loads((tmp_path / "b" / "results.json").read_text())["results"]["modal"]["rows"]
    assert f_first == f_second
