// SPDX-License-Identifier: MIT
// ProgressFn: made from either callback shape, empty = never cancel, the search-level detail
// reaches a callback that takes events and is dropped for one that takes (stage, fraction).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "common/progress.h"

namespace omnislice {

TEST(Progress, EmptyCallbackNeverCancels) {
  const ProgressFn none;
  EXPECT_FALSE(none);
  EXPECT_TRUE(reportProgress(none, "slice", 0.5));
  EXPECT_TRUE(reportProgress(none, "decompose", 0.5, SearchLevelProgress{"beam", 2, 1.5, 8}));
  const ProgressFn null = nullptr;
  EXPECT_FALSE(null);
}

TEST(Progress, EventCallbackSeesTheSearchLevel) {
  std::vector<std::string> seen;
  const ProgressFn fn = [&](const ProgressEvent& e) {
    std::string s = std::string(e.stage) + " " + std::to_string(e.fraction);
    if (e.search) {
      s += std::string(" ") + e.search->line + " " + std::to_string(e.search->level) + " " +
           std::to_string(e.search->jgMm2) + " " + std::to_string(e.search->beams);
    }
    seen.push_back(s);
    return e.search == nullptr || e.search->level < 3;
  };
  ASSERT_TRUE(fn);
  EXPECT_TRUE(reportProgress(fn, "slice", 0.25));
  EXPECT_TRUE(reportProgress(fn, "decompose", 0.5, SearchLevelProgress{"beam", 2, 1.5, 8}));
  // The callback's false cancels, whatever the shape of the report.
  EXPECT_FALSE(reportProgress(fn, "decompose", 0.75, SearchLevelProgress{"chosen", 3, 0.0, 0}));
  ASSERT_EQ(seen.size(), 3u);
  EXPECT_EQ(seen[0], "slice 0.250000");
  EXPECT_EQ(seen[1], "decompose 0.500000 beam 2 1.500000 8");
  EXPECT_EQ(seen[2], "decompose 0.750000 chosen 3 0.000000 0");
}

TEST(Progress, StageFractionCallbackGetsEveryReportWithoutTheDetail) {
  std::vector<std::string> seen;
  const ProgressFn fn = [&](const char* stage, double fraction) {
    seen.push_back(std::string(stage) + " " + std::to_string(fraction));
    return fraction < 0.9;
  };
  ASSERT_TRUE(fn);
  EXPECT_TRUE(reportProgress(fn, "slice", 0.25));
  EXPECT_TRUE(reportProgress(fn, "decompose", 0.5, SearchLevelProgress{"greedy", 1, 10, 1}));
  EXPECT_FALSE(reportProgress(fn, "decompose", 1.0, SearchLevelProgress{"chosen", 0, 10, 0}));
  EXPECT_EQ(seen, (std::vector<std::string>{"slice 0.250000", "decompose 0.500000", "decompose 1.000000"}));
  // A copy calls the same callable (state shared through the captures).
  const ProgressFn copy = fn;
  EXPECT_TRUE(reportProgress(copy, "program", 0));
  EXPECT_EQ(seen.size(), 4u);
}

}  // namespace omnislice
