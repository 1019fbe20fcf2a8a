"""``source scripts/env.sh`` (README) changes nothing in the user's shell but PATH.

The setup it runs (scripts/venv.sh) is strict (``set -euo pipefail``); sourced
into an interactive shell, those options would close the terminal on the next
failing command. Here a shell sources env.sh from a copy of the project whose
.venv is already up to date (no install), and from one whose setup fails.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

# The shell's state, printed before and after `source`: options, shopt, variable names,
# exported environment (PATH and the per-command `_` aside) and working folder.
_STATE = ('{ set -o; shopt; compgen -v | grep -Ev "^(_|BASH_.*|PIPESTATUS|LINENO|RANDOM|SECONDS|SRANDOM|EPOCH.*|'
          'FUNCNAME|BASH_COMMAND|OLDPWD)$"; env | grep -Ev "^(PATH|_|OLDPWD)=" | sort; pwd; } ')


def _project_copy(tmp_path: Path, up_to_date: bool) -> Path:
    root = tmp_path / "project"
    shutil.copytree(ROOT / "scripts", root / "scripts")
    for name in ("requirements.lock", "pyproject.toml"):
        shutil.copy(ROOT / name, root / name)
    bin_ = root / ".venv" / "bin"
    bin_.mkdir(parents=True)
    (bin_ / "python").write_text("#!/bin/sh\nexit 0\n")
    (bin_ / "python").chmod(0o755)
    if up_to_date:       # the stamp venv.sh writes after installing: sha256 of the two files' sha256sum lines
        lines = "".join(f"{hashlib.sha256((root / n).read_bytes()).hexdigest()}  {root / n}\n"
                        for n in ("requirements.lock", "pyproject.toml"))
        (root / ".venv" / ".lock-stamp").write_text(hashlib.sha256(lines.encode()).hexdigest()[:16] + "\n")
    else:
        (root / "requirements.lock").unlink()          # the setup's first step fails
    return root


def _source(root: Path) -> subprocess.CompletedProcess:
    script = (f"set +euo pipefail; {_STATE} > before; "
              f"source {root}/scripts/env.sh; echo \"status $?\"; "
              f"{_STATE} > after; diff before after && echo same-state; "
              "false; echo alive after a failing command; echo \"PATH=$PATH\"")
    env = {k: v for k, v in os.environ.items() if not k.startswith("BASH_FUNC_")}
    return subprocess.run(["bash", "--norc", "--noprofile", "-c", script], cwd=root.parent,
                          capture_output=True, text=True, env=env, timeout=60)


def test_sourcing_changes_only_path(tmp_path):
    root = _project_copy(tmp_path, up_to_date=True)
    proc = _source(root)
    assert "status 0" in proc.stdout, proc.stdout + proc.stderr
    assert "same-state" in proc.stdout, proc.stdout
    assert "alive after a failing command" in proc.stdout
    path = proc.stdout.split("PATH=")[-1].strip().split(":")
    assert path[0] == str(root / ".venv" / "bin")
    assert proc.stderr == ""                               # up to date: nothing installed, nothing said


def test_sourcing_twice_puts_the_venv_on_path_once(tmp_path):
    root = _project_copy(tmp_path, up_to_date=True)
    proc = subprocess.run(["bash", "--norc", "-c", f"source {root}/scripts/env.sh; source {root}/scripts/env.sh; "
                           "echo \"$PATH\""], capture_output=True, text=True, timeout=60)
    assert proc.stdout.split(":").count(str(root / ".venv" / "bin")) == 1


def test_a_failed_setup_returns_its_status_and_keeps_the_shell(tmp_path):
    root = _project_copy(tmp_path, up_to_date=False)
    proc = _source(root)
    assert "status 1" in proc.stdout, proc.stdout + proc.stderr
    assert "same-state" in proc.stdout, proc.stdout
    assert "alive after a failing command" in proc.stdout
    assert str(root / ".venv" / "bin") not in proc.stdout.split("PATH=")[-1]
    assert proc.stderr.strip().splitlines()[-1].startswith("error: scripts/env.sh:")


def test_main_and_test_scripts_stay_strict():
    for name in ("main.sh", "test.sh", "venv.sh"):
        assert "set -euo pipefail" in (ROOT / "scripts" / name).read_text(), name
    assert "set -" not in (ROOT / "scripts" / "env.sh").read_text().replace("set -o", "")
