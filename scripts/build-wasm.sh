#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Build the WebAssembly module: build/wasm/omnislice.mjs + omnislice.wasm (+ omnislice.js wrapper
# and omnislice.d.ts copied next to them). Runs scripts/wasm-deps.sh first (cached).
# Usage: scripts/build-wasm.sh [BUILD_DIR=build/wasm]   env: JOBS (default 2), BUILD_TYPE (Release)
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
BUILD="${1:-build/wasm}"
JOBS="${JOBS:-2}"
export NODE_PATH="${NODE_PATH:-/usr/share/nodejs}"   # em* tools need Debian's acorn (TOOLCHAIN.md)

bash scripts/wasm-deps.sh "${DEPS_DIR:-$ROOT/build/deps}"

if [ ! -f "$BUILD/build.ninja" ]; then
  emcmake cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE="${BUILD_TYPE:-Release}" \
    -DOMNISLICE_WASM_DEPS="${DEPS_DIR:-$ROOT/build/deps}"
fi
cmake --build "$BUILD" -j"$JOBS" --target omnislice_wasm omnislice_wasm_js
for f in omnislice.mjs omnislice.wasm omnislice.js omnislice.d.ts; do
  [ -f "$BUILD/$f" ] || { echo "[build-wasm] error: $BUILD/$f missing" >&2; exit 1; }
done
echo "[build-wasm] $(du -h "$BUILD/omnislice.wasm" | cut -f1) $BUILD/omnislice.wasm" >&2
