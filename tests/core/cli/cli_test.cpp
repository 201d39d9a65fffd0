// SPDX-License-Identifier: MIT
// The omnislice CLI as a user runs it: exit codes, the one-line error format, no partial files.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>

#include "../test_meshes.h"
#include "../pipeline/pipeline_fixtures.h"
#include "../test_support.h"

namespace omnislice {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

struct CliRun {
  int exitCode = -1;
  bool signalled = false;
  std::string out;
  std::string err;
};

CliRun runCli(const std::string& args) {
  const fs::path dir = test::tempDir();
  // ctest runs tests in parallel processes: name the capture files after this process.
  static int calls = 0;
  const std::string tag = std::to_string(::getpid()) + "_" + std::to_string(++calls);
  const fs::path outFile = dir / ("cli_stdout_" + tag + ".txt");
  const fs::path errFile = dir / ("cli_stderr_" + tag + ".txt");
  const std::string cmd = std::string(OMNISLICE_CLI_PATH) + " " + args + " >" + outFile.string() +
                          " 2>" + errFile.string();
  const int raw = std::system(cmd.c_str());
  CliRun r;
  if (WIFEXITED(raw)) r.exitCode = WEXITSTATUS(raw);
  // A shell reports a child killed by a signal as 128 + signal.
  r.signalled = WIFSIGNALED(raw) || (WIFEXITED(raw) && WEXITSTATUS(raw) > 128);
  std::ifstream o(outFile), e(errFile);
  std::stringstream so, se;
  so << o.rdbuf();
  se << e.rdbuf();
  r.out = so.str();
  r.err = se.str();
  fs::remove(outFile);
  fs::remove(errFile);
  return r;
}

fs::path writeTemp(const std::string& name, const std::vector<uint8_t>& bytes) {
  const fs::path p = test::tempDir() / name;
  std::ofstream f(p, std::ios::binary);
  f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  return p;
}

// Exactly one line "error: <code>: <message>" on stderr and exit code 2.
void expectError(const CliRun& r, const std::string& code) {
  EXPECT_FALSE(r.signalled);
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_EQ(r.err.rfind("error: " + code + ": ", 0), 0u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST(Cli, InfoPrintsJson) {
  const fs::path box = writeTemp("cli_box.stl", test::binaryStl(test::makeBox(0, 0, 0, 10, 20, 30)));
  CliRun r = runCli("info " + box.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const Json j = Json::parse(r.out);
  for (const char* k : {"vertices", "faces", "shells", "closed", "manifold", "volume_mm3",
                        "area_mm2", "bbox", "repairs", "errors"}) {
    EXPECT_TRUE(j.contains(k)) << k;
  }
  EXPECT_EQ(j["vertices"].get<int>(), 8);
  EXPECT_EQ(j["faces"].get<int>(), 12);
  EXPECT_NEAR(j["volume_mm3"].get<double>(), 6000, 1e-6);
  EXPECT_NEAR(j["area_mm2"].get<double>(), 2 * (200 + 300 + 600), 1e-6);
  EXPECT_TRUE(j["closed"].get<bool>());
}

TEST(Cli, SliceWritesProgramAndReport) {
  const fs::path box = writeTemp("cli_box2.stl", test::binaryStl(test::makeBox(0, 0, 0, 10, 10, 4)));
  const fs::path gcode = test::tempDir() / "cli_box2.gcode";
  const fs::path report = test::tempDir() / "cli_box2.json";
  fs::remove(gcode);
  CliRun r = runCli("slice " + box.string() + " -o " + gcode.string() + " --layer-height 0.25 --walls 3 " +
                 "--infill 30 --set infill_pattern=lines --report " + report.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  ASSERT_TRUE(fs::exists(gcode));
  std::ifstream rf(report);
  const Json j = Json::parse(rf);
  EXPECT_EQ(j["layers"].get<int>(), 16);
  EXPECT_EQ(j["settings"]["walls"].get<std::string>(), "3");
  EXPECT_EQ(j["settings"]["infill_pattern"].get<std::string>(), "lines");
  EXPECT_GT(j["path_mm"].get<double>(), 0);
  CliRun v = runCli("verify " + gcode.string() + " --mesh " + box.string());
  ASSERT_EQ(v.exitCode, 0) << v.err;
  const Json vj = Json::parse(v.out);
  EXPECT_GE(vj["inside"].get<double>(), 0.99);
  EXPECT_EQ(vj["layers"].get<int>(), 16);
}

// --progress: a line at each stage's start and end, and one per level of a multidir search
// ("progress: decompose P% search level K: J_G = X mm^2 (LINE[, N beams])"); the chosen levels
// are the report's J_G per level, the search lines' levels >= 1 its level count.
TEST(Cli, ProgressPrintsStagesAndSearchLevels) {
  const fs::path l = writeTemp("cli_l.stl", test::binaryStl(test::makeLBracket(10)));
  const fs::path gcode = test::tempDir() / "cli_l.gcode";
  const fs::path report = test::tempDir() / "cli_l.json";
  CliRun r = runCli("slice " + l.string() + " -o " + gcode.string() + " --method multidir --machine table5 " +
                    "--layer-height 0.3 --progress --report " + report.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  std::ifstream rf(report);
  const Json m = Json::parse(rf)["multidir"];
  EXPECT_NE(r.err.find("progress: read 0%\n"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("progress: program 100%\n"), std::string::npos) << r.err;
  // Outside the search levels, a stage's lines alternate: start (0 %), end (100 %), never the
  // same end twice in a row (validate used to print its 100 % twice).
  {
    std::istringstream stages(r.err);
    std::string previous;
    for (std::string line; std::getline(stages, line);) {
      if (line.find("search level") != std::string::npos) continue;
      if (line.find(" 100%") != std::string::npos) {
        EXPECT_NE(line, previous) << r.err;
      }
      previous = line;
    }
  }
  const std::regex level(R"(progress: decompose \d+% search level (\d+): J_G = ([0-9.]+) mm\^2 \((greedy|constrained|beam|chosen)(, \d+ beams?)?\))");
  std::istringstream lines(r.err);
  std::string line;
  size_t searched = 0;
  std::vector<std::string> chosen;
  while (std::getline(lines, line)) {
    if (line.find("search level") == std::string::npos) continue;
    std::smatch g;
    ASSERT_TRUE(std::regex_match(line, g, level)) << line;
    if (g[3] == "chosen") {
      EXPECT_EQ(std::stoi(g[1]), static_cast<int>(chosen.size())) << line;
      chosen.push_back(g[2]);
    } else if (std::stoi(g[1]) >= 1) {
      ++searched;
    }
  }
  EXPECT_EQ(searched, m["search"]["levels"].get<size_t>()) << r.err;
  const auto perLevel = m["search"]["J_G_per_level"].get<std::vector<double>>();
  ASSERT_EQ(chosen.size(), perLevel.size()) << r.err;
  char text[64];
  std::snprintf(text, sizeof text, "%.2f", perLevel.front());
  EXPECT_EQ(chosen.front(), text);
  std::snprintf(text, sizeof text, "%.2f", perLevel.back());
  EXPECT_EQ(chosen.back(), text);
}

// Bad input and options: exit 2, one error line, and no output file left behind.
TEST(Cli, BadInputNeverLeavesPartialFiles) {
  const fs::path out = test::tempDir() / "cli_bad.gcode";
  fs::remove(out);
  const fs::path garbage = writeTemp("cli_garbage.stl", test::bytesOf("solid nonsense\nfacet?\n"));
  const fs::path empty = writeTemp("cli_empty.stl", {});
  const auto good = writeTemp("cli_good.stl", test::binaryStl(test::makeBox(0, 0, 0, 5, 5, 5)));
  auto full = test::binaryStl(test::makeBox(0, 0, 0, 5, 5, 5));
  full.resize(full.size() - 30);
  const fs::path truncated = writeTemp("cli_trunc.stl", full);

  expectError(runCli("slice /nonexistent/x.stl -o " + out.string()), "io_error");
  expectError(runCli("slice " + empty.string() + " -o " + out.string()), "empty_input");
  expectError(runCli("slice " + truncated.string() + " -o " + out.string()), "truncated_file");
  expectError(runCli("slice " + good.string() + " -o " + out.string() + " --set nope=1"),
              "invalid_option");
  expectError(runCli("slice " + good.string() + " -o " + out.string() + " --layer-height -3"),
              "invalid_option");
  expectError(runCli("slice " + good.string() + " -o " + out.string() + " --layer-height nan"),
              "invalid_option");
  expectError(runCli("slice " + good.string() + " -o " + out.string() + " --method voodoo"),
              "invalid_option");
  expectError(runCli("slice " + good.string()), "invalid_option");  // no -o
  expectError(runCli("frobnicate"), "invalid_option");
  expectError(runCli("slice " + good.string() + " -o " + out.string() + " --bogus"), "invalid_option");
  CliRun r = runCli("slice " + garbage.string() + " -o " + out.string());
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_FALSE(r.signalled);
  EXPECT_FALSE(fs::exists(out));
  // Output folder that does not exist: io_error, nothing written.
  expectError(runCli("slice " + good.string() + " -o /nonexistent-dir/out.gcode"), "io_error");
  // A voxel grid larger than the memory budget: out_of_memory naming the setting, nothing written.
  const auto big = writeTemp("cli_big.stl", test::binaryStl(test::makeBox(0, 0, 0, 40, 40, 40)));
  CliRun oom = runCli("slice " + big.string() + " -o " + out.string() +
                      " --method voxel --machine table5 --set memory_mb=16");
  expectError(oom, "out_of_memory");
  EXPECT_NE(oom.err.find("memory_mb = 16 MB"), std::string::npos) << oom.err;
  EXPECT_NE(oom.err.find("voxel.width_mm"), std::string::npos) << oom.err;
  EXPECT_FALSE(fs::exists(out));
}

TEST(Cli, SharedModelsInfo) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const std::string open = (test::sharedModelsDir() / "compas_connection3legs_open_low_res.obj").string();
  CliRun r = runCli("info " + open + " --set repair=none");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const Json j = Json::parse(r.out);
  EXPECT_FALSE(j["closed"].get<bool>());
  EXPECT_EQ(j["boundary_edges"].get<int>(), 147);
  ASSERT_FALSE(j["errors"].empty());
  EXPECT_EQ(j["errors"][0].get<std::string>().rfind("open_mesh", 0), 0u);
  // Slicing it with repair = none is refused with the open-mesh code.
  expectError(runCli("slice " + open + " --set repair=none -o " + (test::tempDir() / "open.gcode").string()),
              "open_mesh");
  // repair = auto (the default): the shell's four open ends are closed, info says so.
  r = runCli("info " + open);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const Json fixed = Json::parse(r.out);
  EXPECT_TRUE(fixed["closed"].get<bool>());
  EXPECT_TRUE(fixed["manifold"].get<bool>());
  EXPECT_TRUE(fixed["errors"].empty()) << fixed["errors"].dump();
  EXPECT_EQ(fixed["repair"]["holes_filled"].get<int>(), 4);
}

}  // namespace
}  // namespace omnislice
