#!/usr/bin/env bash
# Install pyHarm (PyPI: pyharm-os), the second harmonic-balance code of tests/test_pyharm.py, into its own
# environment .venv-pyharm: it pins its own numpy and brings jax, so it stays out of the project's .venv;
# the test runs it in a subprocess. Where pip cannot get it, this says so and returns 0: the test then
# skips with that reason.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
VENV="$ROOT/.venv-pyharm"
if [ -x "$VENV/bin/python" ] && "$VENV/bin/python" -c "import pyHarm" >/dev/null 2>&1; then
  exit 0
fi
echo "[pyharm] installing pyharm-os into $VENV" >&2
if ! (python3 -m venv "$VENV" && "$VENV/bin/pip" install -q "pyharm-os==1.2.2" >/dev/null 2>&1); then
  echo "[pyharm] pip could not install pyharm-os; the pyHarm cross-check will be skipped" >&2
fi
