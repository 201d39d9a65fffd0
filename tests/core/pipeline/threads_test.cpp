// SPDX-License-Identifier: MIT
// The loops that run side by side (the `threads` setting, common/parallel.h): the voxel method's
// curved layers (full layers, then the partial layers between each pair) and the curved layers'
// spirals (solid and sparse) make the same program and report on 1, 2 and 4 threads.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "../test_meshes.h"
#include "pipeline/pipeline.h"
#include "pipeline_fixtures.h"

namespace omnislice {
namespace {

using Json = nlohmann::json;

void expectSameOnAnyThreads(Method method, double infill) {
  const std::vector<uint8_t> bytes = test::binaryStl(test::makeLBracket(10));
  Settings s = test::coarseCurvedSettings(method);
  s.infillPercent = infill;
  std::string program;
  Json report;
  for (int threads : {1, 2, 4}) {
    s.threads = threads;
    const SliceOutput out = runSlice(bytes.data(), bytes.size(), "l.stl", s);
    ASSERT_TRUE(out.ok()) << out.message;
    const std::string undated = out.program.substr(out.program.find('\n') + 1);
    const Json r = test::timelessReport(Json::parse(out.reportJson));
    if (threads == 1) {
      program = undated;
      report = r;
      continue;
    }
    EXPECT_EQ(undated, program) << threads << " threads";
    EXPECT_EQ(r, report) << threads << " threads";
  }
}

TEST(Threads, VoxelSolidIsTheSameOnAnyThreads) { expectSameOnAnyThreads(Method::Voxel, 100); }
TEST(Threads, VoxelSparseIsTheSameOnAnyThreads) { expectSameOnAnyThreads(Method::Voxel, 20); }
TEST(Threads, GeodesicSparseIsTheSameOnAnyThreads) { expectSameOnAnyThreads(Method::Geodesic, 20); }

}  // namespace
}  // namespace omnislice
