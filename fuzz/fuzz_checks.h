// SPDX-License-Identifier: MIT
// The fuzz targets' checks (issue 29): every reader of the core fed arbitrary bytes. A check
// returns "" when the input was handled as the reader's contract says (a result or a status with a
// message) and the properties of the result hold; otherwise what was violated. A crash, a hang or
// a sanitizer report is a failure the fuzzer sees itself. The libFuzzer entry points
// (fuzz/fuzz_main.cpp, `npm run fuzz`) abort on a violation; the regression test
// (tests/core/fuzz/fuzz_regression_test.cpp) runs every seed and every crasher found through the
// same checks in the normal build.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace omnislice::fuzz {

struct Target {
  const char* name;  // also the folder of its seeds (fuzz/corpus/NAME) and crashers (fuzz/regressions/NAME)
  std::string (*check)(const uint8_t* data, size_t size);
};

// stl, obj, off, ply, 3mf, inflate, tet, program, machine, settings.
const std::vector<Target>& targets();
const Target* findTarget(const std::string& name);

}  // namespace omnislice::fuzz
