#!/usr/bin/env bash
# Set up the environment (if missing) and run the whole test suite, verification gates included.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$ROOT/scripts/venv.sh"
export PATH="$ROOT/.venv/bin:$PATH"
bash "$ROOT/scripts/install_calculix.sh"
bash "$ROOT/scripts/install_pyharm.sh"
cd "$ROOT"
exec python -m pytest "$@"
