#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Build the native tree (build/native: core, CLI, tests) and/or the wasm module (build/wasm).
# Usage: scripts/build.sh [native|wasm|all]   (default all). Incremental (ninja + ccache).
set -euo pipefail
cd "$(dirname "$0")/.."
what=${1:-all}
jobs=${OMNISLICE_JOBS:-$(nproc)}

if [ "$what" = native ] || [ "$what" = all ]; then
  echo "build: native (build/native)"
  if [ ! -f build/native/build.ninja ]; then
    cmake -S . -B build/native -G Ninja -DCMAKE_BUILD_TYPE=Release
  fi
  cmake --build build/native -j "$jobs"
fi
if [ "$what" = wasm ] || [ "$what" = all ]; then
  echo "build: wasm (build/wasm)"
  bash scripts/build-wasm.sh
fi
