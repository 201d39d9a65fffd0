#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# npm run test:sanitize: the native core, CLI and tests built with AddressSanitizer and
# UndefinedBehaviorSanitizer (build/sanitize, OMNISLICE_SANITIZE=ON, -O2 -g), then every ctest test
# under them. Any sanitizer report stops its test and fails the run. Not part of `npm test` (a
# second native build and about 3x slower tests). Arguments go to ctest (e.g. -R Voxel).
set -uo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
bash scripts/bootstrap.sh || exit 1
if [ ! -f build/sanitize/build.ninja ]; then
  cmake -S . -B build/sanitize -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DOMNISLICE_SANITIZE=ON || exit 1
fi
cmake --build build/sanitize -j "${OMNISLICE_JOBS:-$(nproc)}" || { echo "sanitize: build failed" >&2; exit 1; }
# halt_on_error: the first report ends the test (so ctest counts it as failed); leaks are reported
# at exit. Stack traces symbolised from the -g build.
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:strict_string_checks=1:check_initialization_order=1:detect_stack_use_after_return=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
status=0
ctest --test-dir build/sanitize --output-on-failure -j 2 --timeout 3600 "$@" || status=1
echo "sanitize: finished in $(( $(date +%s) - start )) s, $( [ $status -eq 0 ] && echo clean || echo FAILED )"
exit $status
