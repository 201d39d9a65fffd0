#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# npm run test:sanitize: the native core, CLI and tests built with AddressSanitizer and
# UndefinedBehaviorSanitizer (build/sanitize, OMNISLICE_SANITIZE=ON, -O2 -g), then every ctest test
# under them. Any sanitizer report stops its test and fails the run. Not part of `npm test` (a
# second native build and about 3x slower tests). Arguments go to ctest (e.g. -R Voxel).
# OMNISLICE_SANITIZE_PHASE=ctest | cli runs one of the two phases (default both);
# OMNISLICE_SANITIZE_MODELS="A B ..." slices those files in the CLI phase instead of the shared ones.
set -uo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
bash scripts/bootstrap.sh || exit 1
if [ ! -f build/sanitize/build.ninja ]; then
  cmake -S . -B build/sanitize -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DOMNISLICE_SANITIZE=ON || exit 1
fi
targets=()
[ "${OMNISLICE_SANITIZE_PHASE:-all}" = cli ] && targets=(--target omnislice)
cmake --build build/sanitize -j "${OMNISLICE_JOBS:-$(nproc)}" "${targets[@]}" ||
  { echo "sanitize: build failed" >&2; exit 1; }
# halt_on_error: the first report ends the test (so ctest counts it as failed); leaks are reported
# at exit. Stack traces symbolised from the -g build.
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:strict_string_checks=1:check_initialization_order=1:detect_stack_use_after_return=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
status=0
if [ "${OMNISLICE_SANITIZE_PHASE:-all}" != cli ]; then
  # Every test (none bounds a wall time: speed is measured by `npm run bench`). Each test's limit
  # is 3 h in this build (tests/CMakeLists.txt).
  ctest --test-dir build/sanitize --output-on-failure -j 2 "$@" || status=1
fi
# Then the CLI on real files: every closed shared model (when ../shared is there), the open ones
# (repaired), and malformed bytes, sliced with every method on its machine at 20 mm and the
# programs verified, each under the sanitizers. A refusal (an error code) is fine; a report is not.
if [ "${OMNISLICE_SANITIZE_PHASE:-all}" != ctest ]; then
  cli=build/sanitize/omnislice
  out=build/sanitize/cli
  mkdir -p "$out"
  models=()
  if [ -n "${OMNISLICE_SANITIZE_MODELS:-}" ]; then
    read -r -a models <<< "$OMNISLICE_SANITIZE_MODELS"
  else
    for f in ../shared/models/*.{stl,obj,off,ply,tet}; do [ -f "$f" ] && models+=("$f"); done
  fi
  head -c 3000 web/models/demo-overhang.stl > "$out/truncated.stl"
  printf 'solid x\nfacet normal 0 0 1\nouter loop\nvertex nan 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid\n' > "$out/nan.stl"
  models+=(web/models/demo-overhang.stl web/models/demo-saddle.obj "$out/truncated.stl" "$out/nan.stl")
  runs=0
  # Runs the CLI (stderr to ERR_FILE); 0 when it exited 0, 2 when it refused cleanly (exit 2, no
  # report), 1 (and status=1, the report shown) on a sanitizer report or any other exit.
  run_cli() {
    local label=$1 err=$2
    shift 2
    "$cli" "$@" > /dev/null 2> "$err"
    local rc=$?
    runs=$((runs + 1))
    if grep -q "Sanitizer\|runtime error" "$err" || { [ $rc -ne 0 ] && [ $rc -ne 2 ]; }; then
      echo "sanitize: $label: exit $rc" >&2
      grep -m 20 "ERROR\|runtime error\|SUMMARY\|#[0-9] " "$err" >&2
      status=1
      return 1
    fi
    return $rc
  }
  for m in "${models[@]}"; do
    for mm in "planar cartesian3" "multidir table5" "voxel table5" "geodesic robot6-ur5" "surface table5"; do
      set -- $mm
      name=$(basename "$m"); name=${name%.*}-$1
      run_cli "$name" "$out/$name.err" slice "$m" -o "$out/$name.prog" --method "$1" --machine "$2" \
        --fit-mm 20 --set verify=warn --set verify_attempts=1 || continue
      run_cli "verify $name" "$out/$name.verify.err" verify "$out/$name.prog" --mesh "$m" -o /dev/null
    done
  done
  echo "sanitize: CLI: ${#models[@]} files, $runs runs (slice and verify)"
fi
echo "sanitize: finished in $(( $(date +%s) - start )) s, $( [ $status -eq 0 ] && echo clean || echo FAILED )"
exit $status
