// SPDX-License-Identifier: MIT
// Slice bytes with settings through the pipeline and verify the program against the same bytes:
// the method tests' end-to-end fixture (report and verify JSON parsed; failures are test failures).
#pragma once
#include <gtest/gtest.h>

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pipeline/pipeline.h"

namespace omnislice::test {

struct Sliced {
  SliceOutput out;
  nlohmann::json report, verify;
};

inline Sliced sliceAndVerify(const std::vector<uint8_t>& bytes, const std::string& name, const Settings& s) {
  Sliced r;
  r.out = runSlice(bytes.data(), bytes.size(), name, s);
  EXPECT_TRUE(r.out.ok()) << r.out.message;
  if (!r.out.ok()) return r;
  r.report = nlohmann::json::parse(r.out.reportJson);
  VerifyOutput v = runVerify(r.out.program, bytes.data(), bytes.size(), name);
  EXPECT_TRUE(v.ok()) << v.message;
  if (v.ok()) r.verify = nlohmann::json::parse(v.verifyJson);
  return r;
}

}  // namespace omnislice::test
