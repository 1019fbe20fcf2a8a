#!/usr/bin/env bash
# Set up the environment and run the bundled default scene into out/default.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$ROOT/scripts/env.sh"
cd "$ROOT"
exec shroud run scenes/default.toml --out "${1:-out/default}"
