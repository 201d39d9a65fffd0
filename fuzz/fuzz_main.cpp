// SPDX-License-Identifier: MIT
// libFuzzer entry point of one target (OMNISLICE_FUZZ_TARGET names it; fuzz/CMakeLists.txt builds
// one binary per target): a violated property aborts, so libFuzzer keeps the input as a crasher.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "fuzz_checks.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const omnislice::fuzz::Target* target = omnislice::fuzz::findTarget(OMNISLICE_FUZZ_TARGET);
  if (!target) std::abort();
  const std::string problem = target->check(data, size);
  if (!problem.empty()) {
    std::fprintf(stderr, "fuzz %s: %s\n", target->name, problem.c_str());
    std::abort();
  }
  return 0;
}
