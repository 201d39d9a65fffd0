// SPDX-License-Identifier: MIT
#include <gtest/gtest.h>

#include "pipeline/settings.h"

namespace omnislice {

// Every listed setting can be set back from its own text: --set and headers round-trip.
TEST(Settings, ListRoundTrips) {
  Settings s;
  ASSERT_TRUE(setSetting(s, "layer_height", "0.15").ok());
  ASSERT_TRUE(setSetting(s, "walls", "3").ok());
  ASSERT_TRUE(setSetting(s, "infill_pattern", "lines").ok());
  ASSERT_TRUE(setSetting(s, "direction", "0,1,1").ok());
  ASSERT_TRUE(setSetting(s, "up", "-y").ok());
  const auto listed = listSettings(s);
  Settings t;
  for (const auto& [k, v] : listed) {
    Outcome o = setSetting(t, k, v);
    EXPECT_TRUE(o.ok()) << k << " = " << v << ": " << o.message;
  }
  EXPECT_EQ(listSettings(t), listed);
  EXPECT_DOUBLE_EQ(t.layerHeight, 0.15);
  EXPECT_EQ(t.walls, 3);
  EXPECT_NEAR(t.direction.norm(), 1.0, 1e-12);
  EXPECT_NEAR(t.direction.y(), std::sqrt(0.5), 1e-12);
  EXPECT_EQ(t.placement.up, UpAxis::NegY);
}

// Bad values name the key and never change the setting.
TEST(Settings, RejectsAbsurdValues) {
  Settings s;
  const Settings before = s;
  for (const auto& [k, v] : std::vector<std::pair<std::string, std::string>>{
           {"layer_height", "-1"}, {"layer_height", "nan"}, {"layer_height", "inf"},
           {"layer_height", "0.2mm"}, {"walls", "2.5"}, {"walls", "-1"}, {"infill", "101"},
           {"direction", "0,0,0"}, {"direction", "1,2"}, {"up", "w"}, {"nope", "1"},
           {"method", "magic"}, {"scale", "0"}, {"center", "maybe"}}) {
    Outcome o = setSetting(s, k, v);
    EXPECT_EQ(o.status, Status::InvalidOption) << k << "=" << v;
    EXPECT_NE(o.message.find(k == "nope" ? "nope" : k), std::string::npos) << o.message;
  }
  EXPECT_EQ(listSettings(s), listSettings(before));
}

// Cross-field checks: a layer thicker than the nozzle cannot be printed.
TEST(Settings, ValidateCrossFields) {
  Settings s;
  EXPECT_TRUE(validateSettings(s).ok());
  ASSERT_TRUE(setSetting(s, "layer_height", "0.6").ok());
  EXPECT_EQ(validateSettings(s).status, Status::InvalidOption);
  ASSERT_TRUE(setSetting(s, "nozzle", "0.8").ok());
  EXPECT_TRUE(validateSettings(s).ok());
}

}  // namespace omnislice
