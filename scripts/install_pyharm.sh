#!/usr/bin/env bash
# Install pyHarm (PyPI package pyharm-os), the second harmonic-balance code of tests/test_pyharm.py,
# in a virtual environment of its own, .venv-pyharm: its wheel needs numpy < 2.5 and jax < 0.6 while the
# project pins numpy 2.5.5, so the two cannot share .venv. Where it cannot be installed (no Python >= 3.12,
# no network, pip refused) it says so in one line and returns 0: the cross-check tests then skip with that
# reason (docs/pyharm.md).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
VENV="$ROOT/.venv-pyharm"
PACKAGE="pyharm-os==1.2.2"

if [ -x "$VENV/bin/python" ] && "$VENV/bin/python" -c 'import pyHarm' >/dev/null 2>&1; then
  exit 0
fi
source "$ROOT/scripts/find_python.sh"
PY="$(find_python)" || { echo "[pyharm] no Python >= 3.12 found; the pyHarm cross-check will be skipped" >&2; exit 0; }
echo "[pyharm] installing $PACKAGE into .venv-pyharm" >&2
if ! { [ -x "$VENV/bin/python" ] || "$PY" -m venv "$VENV" >/dev/null 2>&1; } \
   || ! "$VENV/bin/python" -m pip install -q "$PACKAGE" >/dev/null 2>&1; then
  echo "[pyharm] pip could not install $PACKAGE (no network or refused); the pyHarm cross-check will be skipped" >&2
fi
