#!/usr/bin/env bash
# Install CalculiX (ccx), the second FE code of scenes/calculix.toml and tests/test_calculix.py,
# where this machine allows it: as root with apt-get (Debian/Ubuntu package calculix-ccx).
# Elsewhere it says so and returns 0: the cross-check tests then skip with that reason.
set -euo pipefail
if command -v ccx >/dev/null 2>&1; then
  exit 0
fi
if [ "$(id -u)" = "0" ] && command -v apt-get >/dev/null 2>&1; then
  echo "[calculix] installing calculix-ccx with apt-get" >&2
  if ! (apt-get install -y -q calculix-ccx >/dev/null 2>&1 || \
        (apt-get update -q >/dev/null 2>&1 && apt-get install -y -q calculix-ccx >/dev/null 2>&1)); then
    echo "[calculix] apt-get could not install calculix-ccx; the CalculiX cross-check will be skipped" >&2
  fi
else
  echo "[calculix] ccx not found and not installable here (needs root and apt-get); the CalculiX" \
       "cross-check will be skipped (see the README: CalculiX)" >&2
fi
