#!/usr/bin/env bash
# Create (or reuse) the project's .venv on Python >= 3.12 with pinned dependencies.
# Run as its own process (by env.sh, main.sh, test.sh), so its strict mode stays here;
# safe to run again (it only installs when the lock changed).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
VENV="$ROOT/.venv"
STAMP="$VENV/.lock-stamp"

source "$ROOT/scripts/find_python.sh"

want="$(sha256sum "$ROOT/requirements.lock" "$ROOT/pyproject.toml" | sha256sum | cut -c1-16)"
if [ ! -x "$VENV/bin/python" ] || [ "$(cat "$STAMP" 2>/dev/null)" != "$want" ]; then
  if [ ! -x "$VENV/bin/python" ]; then
    PY="$(find_python)" || { echo "error: Python >= 3.12 is needed (python3.13 or python3.12 on PATH, or under ~/.pyenv/versions); none found" >&2; exit 1; }
    echo "[env] creating .venv with $PY" >&2
    "$PY" -m venv "$VENV"
  fi
  echo "[env] installing pinned dependencies (requirements.lock)" >&2
  "$VENV/bin/python" -m pip install -q --upgrade pip >&2
  "$VENV/bin/python" -m pip install -q -r "$ROOT/requirements.lock" >&2
  "$VENV/bin/python" -m pip install -q --no-deps -e "$ROOT" >&2
  echo "$want" > "$STAMP"
fi
