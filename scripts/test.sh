#!/usr/bin/env bash
# Set up the environment (if missing) and run the whole test suite, verification gates included.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$ROOT/scripts/env.sh"
bash "$ROOT/scripts/install_calculix.sh"
bash "$ROOT/scripts/install_pyharm.sh"
cd "$ROOT"
exec python -m pytest "$@"
