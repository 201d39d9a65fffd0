// SPDX-License-Identifier: MIT
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "common/status.h"

namespace omnislice {

// Every status has its own stable, distinct code (JS mirrors them by string).
TEST(Status, CodesAreDistinct) {
  std::set<std::string> codes;
  for (int s = 0; s <= static_cast<int>(Status::Internal); ++s) {
    codes.insert(statusCode(static_cast<Status>(s)));
  }
  EXPECT_EQ(codes.size(), static_cast<size_t>(Status::Internal) + 1);
  EXPECT_STREQ(statusCode(Status::OpenMesh), "open_mesh");
  EXPECT_STREQ(statusCode(Status::OutOfMemory), "out_of_memory");
}

}  // namespace omnislice
