#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Every test: install what is missing, build both targets, then ctest (C++), the wasm module and
# worker protocol in Node/Chromium (tests/js), and the page end to end in headless Chromium
# (tests/e2e). Exits non-zero on any failure.
set -uo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)

bash scripts/bootstrap.sh || exit 1
bash scripts/build.sh all || { echo "test: build failed" >&2; exit 1; }

status=0
echo "test: C++ (ctest)"
ctest --test-dir build/native --output-on-failure -j 2 || status=1

echo "test: JavaScript (wasm in Node, worker protocol, page end to end)"
js_tests=$(ls tests/js/*.test.mjs tests/e2e/*.test.mjs 2>/dev/null)
if [ -n "$js_tests" ]; then
  node --test --test-concurrency=1 $js_tests || status=1
fi

echo "test: finished in $(( $(date +%s) - start )) s, $( [ $status -eq 0 ] && echo passed || echo FAILED )"
exit $status
