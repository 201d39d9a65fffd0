// SPDX-License-Identifier: MIT
// The fuzz targets' checks (fuzz/fuzz_checks.h) on the seed corpus (fuzz/corpus/NAME) and on every
// crasher the fuzzers found (fuzz/regressions/NAME, kept once fixed): in the normal build, so a
// reader change that brings a found bug back fails ctest without a fuzzer.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <vector>

#include "fuzz_checks.h"

namespace fs = std::filesystem;

namespace {

std::vector<uint8_t> readBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}

// The files of folder/NAME for every target: (target, file).
std::vector<std::pair<const omnislice::fuzz::Target*, fs::path>> inputs(const char* folder) {
  std::vector<std::pair<const omnislice::fuzz::Target*, fs::path>> out;
  for (const auto& t : omnislice::fuzz::targets()) {
    const fs::path dir = fs::path(OMNISLICE_FUZZ_DIR) / folder / t.name;
    if (!fs::is_directory(dir)) continue;
    std::set<fs::path> files;  // sorted: the same order everywhere
    for (const auto& e : fs::directory_iterator(dir)) {
      if (e.is_regular_file()) files.insert(e.path());
    }
    for (const auto& f : files) out.emplace_back(&t, f);
  }
  return out;
}

}  // namespace

TEST(Fuzz, EveryTargetHasSeedsTheChecksPass) {
  const auto seeds = inputs("corpus");
  for (const auto& t : omnislice::fuzz::targets()) {
    size_t n = 0;
    for (const auto& [target, file] : seeds) n += target == &t;
    EXPECT_GE(n, 1u) << "no seed in fuzz/corpus/" << t.name;
  }
  for (const auto& [target, file] : seeds) {
    const std::vector<uint8_t> bytes = readBytes(file);
    EXPECT_EQ(target->check(bytes.data(), bytes.size()), "") << target->name << " seed " << file.filename();
  }
}

TEST(Fuzz, CrashersFoundStayFixed) {
  for (const auto& [target, file] : inputs("regressions")) {
    const std::vector<uint8_t> bytes = readBytes(file);
    EXPECT_EQ(target->check(bytes.data(), bytes.size()), "") << target->name << " crasher " << file.filename();
  }
}

// The checks see what they are meant to: a truncated binary STL is refused with a message, a
// settings line with an unknown key is refused without breaking the round trip, and a machine
// profile that parses round-trips; an empty input is handled by every target.
TEST(Fuzz, ChecksHandleEdgeInputs) {
  for (const auto& t : omnislice::fuzz::targets()) {
    const uint8_t one[1] = {0xff};
    EXPECT_EQ(t.check(one, 0), "") << t.name << " on empty input";
    EXPECT_EQ(t.check(one, 1), "") << t.name << " on one byte";
  }
  const std::string settings = "layer_height=0.3\nno_such_key=1\nwalls=-4\ninfill=35\n";
  EXPECT_EQ(omnislice::fuzz::findTarget("settings")->check(reinterpret_cast<const uint8_t*>(settings.data()),
                                                           settings.size()),
            "");
  EXPECT_EQ(omnislice::fuzz::findTarget("nope"), nullptr);
}
