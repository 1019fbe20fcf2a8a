#!/usr/bin/env bash
# Set up the environment and run the bundled default scene into out/default.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$ROOT/scripts/venv.sh"
export PATH="$ROOT/.venv/bin:$PATH"
cd "$ROOT"
exec shroud run scenes/default.toml --out "${1:-out/default}"
