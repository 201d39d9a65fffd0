#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# npm run fuzz -- [SECONDS] [TARGET...]: every libFuzzer target (fuzz/fuzz_checks.h: the mesh
# readers, 3MF with its zip and inflate, .tet, the program reader, machine JSON, settings) for
# SECONDS each (default 60), from the seeds in fuzz/corpus/NAME plus what earlier runs added
# (build/fuzz/corpus/NAME). Installs clang and its fuzzer runtime when missing (root; not needed by
# `npm test`), builds build/fuzz (clang, ASan + UBSan + coverage), and prints one line
#   fuzz: N targets, R runs, C crashes
# Exits non-zero on any crash. A crasher is kept as build/fuzz/crashes/NAME-*: once fixed, copy it
# to fuzz/regressions/NAME/ (ctest's Fuzz.CrashersFoundStayFixed replays it).
set -uo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
[ $# -gt 0 ] && shift
if ! [[ "$seconds" =~ ^[0-9]+$ ]] || [ "$seconds" -lt 1 ]; then
  echo "fuzz: SECONDS must be a positive integer" >&2
  exit 2
fi
all=(stl obj off ply 3mf inflate tet program machine settings)
if [ $# -gt 0 ]; then targets=("$@"); else targets=("${all[@]}"); fi

bash scripts/bootstrap.sh || exit 1
runtime=$(ls /usr/lib/llvm-*/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a 2>/dev/null | head -1)
if ! command -v clang++ > /dev/null || [ -z "$runtime" ]; then
  if [ "$(id -u)" -ne 0 ]; then
    echo "fuzz: clang and libclang-rt-dev are missing; run 'npm run fuzz' as root once" >&2
    exit 1
  fi
  echo "fuzz: apt-get install clang libclang-rt-dev"
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q clang libclang-rt-dev > /dev/null || exit 1
fi

if [ ! -f build/fuzz/build.ninja ]; then
  CC=clang CXX=clang++ cmake -S . -B build/fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DOMNISLICE_FUZZ=ON -DOMNISLICE_TESTS=OFF > /dev/null || exit 1
fi
cmake --build build/fuzz -j "${OMNISLICE_JOBS:-$(nproc)}" --target $(printf 'fuzz_%s ' "${targets[@]}") ||
  { echo "fuzz: build failed" >&2; exit 1; }

mkdir -p build/fuzz/crashes build/fuzz/logs
total_runs=0
total_crashes=0
for t in "${targets[@]}"; do
  corpus=build/fuzz/corpus/$t
  mkdir -p "$corpus"
  before=$(ls build/fuzz/crashes | grep -c "^$t-" || true)
  # -timeout: an input taking 10 s is a hang (kept as a crasher); -rss_limit_mb: 2 GiB.
  build/fuzz/fuzz/fuzz_"$t" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix=build/fuzz/crashes/"$t"- "$corpus" fuzz/corpus/"$t" > build/fuzz/logs/"$t".log 2>&1
  rc=$?
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' build/fuzz/logs/"$t".log | grep -o '[0-9]*$' | tail -1)
  after=$(ls build/fuzz/crashes | grep -c "^$t-" || true)
  crashes=$((after - before))
  [ $rc -ne 0 ] && [ $crashes -eq 0 ] && crashes=1  # a crash the artifact prefix did not catch
  echo "fuzz: $t: ${runs:-0} runs, $crashes crashes$([ $crashes -gt 0 ] && echo " (build/fuzz/logs/$t.log)")"
  total_runs=$((total_runs + ${runs:-0}))
  total_crashes=$((total_crashes + crashes))
done
echo "fuzz: ${#targets[@]} targets, $total_runs runs, $total_crashes crashes"
[ $total_crashes -eq 0 ]
