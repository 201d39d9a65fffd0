#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Benchmark native vs wasm (needs both builds: scripts/build.sh). Writes build/bench.json.
set -euo pipefail
cd "$(dirname "$0")/.."
[ -x build/native/omnislice ] && [ -f build/wasm/omnislice.mjs ] || bash scripts/build.sh all
exec node scripts/bench.mjs "$@"
