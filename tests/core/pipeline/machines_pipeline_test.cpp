// SPDX-License-Identifier: MIT
// Issue 3's "done when": every machine kind sliced with the planar slicer (d = +Z in the part frame,
// mapped through the machine) writes a program that `verify` replays through the same machine and
// passes; the preview's machine values reproduce the part-frame path through the forward map; the
// report carries the motion figures; bad machine input is a Status.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <nlohmann/json.hpp>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>

#include "../test_meshes.h"
#include "../test_support.h"
#include "common/math_constants.h"
#include "kinematics/kinematics.h"
#include "pipeline/pipeline.h"
#include "pipeline/preview.h"
#include "program/read_program.h"
#include "pipeline_fixtures.h"
#include "machine/machine.h"
#include "machine/machine_json.h"

namespace omnislice {
namespace {

using Json = nlohmann::json;

struct Case {
  const char* machine;
  const char* flavor;
  const char* robotFormat;
  const char* extension;
  const char* firstLine;  // how the program starts
};

// A 16 x 12 x 5 mm box (25 layers of 0.2 mm).
std::vector<uint8_t> testPart() { return test::binaryStl(test::makeBox(0, 0, 0, 16, 12, 5)); }

Settings settingsFor(const Case& c) {
  Settings s;
  EXPECT_TRUE(setSetting(s, "infill", "100").ok());
  EXPECT_TRUE(setSetting(s, "machine", c.machine).ok());
  EXPECT_TRUE(setSetting(s, "gcode_flavor", c.flavor).ok());
  EXPECT_TRUE(setSetting(s, "robot_format", c.robotFormat).ok());
  return s;
}

// The preview's platform poses (quaternion x y z w, translation) against the machine itself, apart
// from platformTransform(): each pose takes the segment's part-frame end point onto the nozzle tip
// (X Y Z of the segment's machine values for the G-code kinds, the fixed nozzle tip for robot6) and
// the part-frame nozzle axis onto the machine's nozzle axis; quaternions are unit and consecutive
// ones lie in one hemisphere. Returns the worst tip distance (mm).
double checkPoses(const ToolpathPreview& p, const MachineProfile& machine, bool withAxes) {
  const size_t segments = p.features.size();
  EXPECT_EQ(p.poses.size(), 7 * segments);
  if (p.poses.size() != 7 * segments) return INFINITY;
  const bool robot = machine.kind == MachineKind::Robot6;
  // head4, head5: the bed stays; the head carries the tip and the axis.
  const bool head = machine.kind == MachineKind::Head5 || machine.kind == MachineKind::Head4;
  double worstTip = 0, worstAxis = 0, worstNorm = 0, worstDot = 1;
  for (size_t i = 0; i < segments; ++i) {
    const float* q = &p.poses[7 * i];
    const Eigen::Quaterniond r(q[3], q[0], q[1], q[2]);  // Eigen takes w x y z
    worstNorm = std::max(worstNorm, std::abs(r.norm() - 1));
    if (i > 0) {
      const float* b = &p.poses[7 * (i - 1)];
      worstDot = std::min(worstDot, double(q[0] * b[0] + q[1] * b[1] + q[2] * b[2] + q[3] * b[3]));
    }
    const Eigen::Vector3d end(p.positions[6 * i + 3], p.positions[6 * i + 4], p.positions[6 * i + 5]);
    const Eigen::Vector3d onMachine = r.normalized() * end + Eigen::Vector3d(q[4], q[5], q[6]);
    MachineValues v{};
    for (int k = 0; k < 6; ++k) v[k] = p.machine[6 * i + k];
    Eigen::Vector3d headTip, headAxis;
    if (head) EXPECT_TRUE(forwardMap(machine, v, headTip, headAxis));
    const Eigen::Vector3d nozzle = robot ? machine.nozzleTip : head ? headTip : Eigen::Vector3d(v[0], v[1], v[2]);
    const Eigen::Vector3d machineAxis = robot ? machine.nozzleAxis : head ? headAxis : Eigen::Vector3d::UnitZ();
    worstTip = std::max(worstTip, (onMachine - nozzle).norm());
    if (withAxes) {
      const Eigen::Vector3d axis(p.axes[3 * i], p.axes[3 * i + 1], p.axes[3 * i + 2]);
      worstAxis = std::max(worstAxis, (r.normalized() * axis - machineAxis).norm());
    }
  }
  EXPECT_LT(worstNorm, 1e-6);
  EXPECT_GE(worstDot, 0.0) << "consecutive quaternions in one hemisphere";
  EXPECT_LT(worstAxis, 1e-5) << "the pose turns the part-frame nozzle axis onto the machine's";
  return worstTip;
}

class MachinesPipeline : public ::testing::TestWithParam<Case> {};

TEST_P(MachinesPipeline, SlicesVerifiesAndReplays) {
  const Case c = GetParam();
  const auto bytes = testPart();
  const Settings s = settingsFor(c);
  SliceOutput out = runSlice(bytes.data(), bytes.size(), "part.stl", s);
  ASSERT_TRUE(out.ok()) << out.message;
  EXPECT_EQ(out.programExtension, c.extension);
  EXPECT_EQ(out.program.rfind(c.firstLine, 0), 0u) << out.program.substr(0, 80);

  const Json report = Json::parse(out.reportJson);
  MachineProfileResult builtin = builtinMachine(c.machine, s.bedSize, s.nozzleDiameter);
  ASSERT_TRUE(builtin.ok()) << builtin.message;
  EXPECT_EQ(report["machine_kind"], machineKindName(builtin.machine.kind));
  EXPECT_EQ(report["layers"].get<int>(), 25);
  for (const char* key : {"samples", "subdivisions", "filtered_orientations", "feed_limited_moves",
                          "safe_rotations", "max_joint_step", "pose_cost", "greedy_pose_cost",
                          "min_singularity"}) {
    EXPECT_TRUE(report["motion"].contains(key)) << key;
  }
  EXPECT_GT(report["motion"]["samples"].get<double>(), 100);
  if (!report["motion"]["greedy_pose_cost"].is_null()) {
    EXPECT_LE(report["motion"]["pose_cost"].get<double>(),
              report["motion"]["greedy_pose_cost"].get<double>() + 1e-9);
  }
  EXPECT_TRUE(report["timings_ms"].contains("motion"));
  // The report's machine profile is the header's, and it parses back.
  MachineParseResult parsed = machineFromJson(report["machine_profile"].dump());
  ASSERT_TRUE(parsed.ok()) << parsed.message;
  EXPECT_EQ(parsed.machine.kind, builtin.machine.kind);

  // The animation data: forwardMap of every preview row lands on the segment's end point.
  const size_t segments = out.preview.toolpath.features.size();
  ASSERT_EQ(out.preview.toolpath.machine.size(), 6 * segments);
  double worst = 0;
  for (size_t i = 0; i < segments; ++i) {
    MachineValues v{};
    for (int k = 0; k < 6; ++k) v[k] = out.preview.toolpath.machine[6 * i + k];
    Eigen::Vector3d tip, axis;
    ASSERT_TRUE(forwardMap(parsed.machine, v, tip, axis));
    const Eigen::Vector3d end(out.preview.toolpath.positions[6 * i + 3], out.preview.toolpath.positions[6 * i + 4],
                              out.preview.toolpath.positions[6 * i + 5]);
    worst = std::max(worst, (tip - end).norm());
  }
  // Float32 preview: joint angles in float lose ~1e-7 rad, ~1e-4 mm at the arm's reach.
  EXPECT_LT(worst, 5e-3) << "forward map of the preview's machine values vs its path";
  // The platform poses the page moves the part with (float32 of the double pose: ~1e-5 mm at a
  // few hundred mm from the origin).
  EXPECT_LT(checkPoses(out.preview.toolpath, parsed.machine, true), 2e-3);
  // The same of the program read back (the page's replay of a program file).
  const ParsedProgram program = readProgram(out.program);
  ASSERT_TRUE(program.ok()) << program.message;
  const ToolpathPreview replay = programPreview(program);
  EXPECT_GT(replay.features.size(), segments / 2);
  EXPECT_LT(checkPoses(replay, program.machine, false), 5e-3);

  // Verification by simulation through the declared machine.
  VerifyOutput v = runVerify(out.program, bytes.data(), bytes.size(), "part.stl");
  ASSERT_TRUE(v.ok()) << v.message;
  const Json vr = Json::parse(v.verifyJson);
  EXPECT_GE(vr["inside"].get<double>(), 0.99) << vr.dump();
  EXPECT_GE(vr["coverage"].get<double>(), 0.95) << vr.dump();
  EXPECT_GE(vr["supported"].get<double>(), 0.99) << vr.dump();
  EXPECT_EQ(vr["collisions"].get<int>(), 0) << vr.dump();
  EXPECT_EQ(vr["limits"].get<int>(), 0) << vr.dump();
  EXPECT_EQ(vr["layers"].get<int>(), 25) << vr.dump();
  EXPECT_NEAR(vr["extrusion_mm"].get<double>(), report["extrusion_mm"].get<double>(),
              2e-3 * report["extrusion_mm"].get<double>());
  EXPECT_NEAR(vr["path_mm"].get<double>(), report["path_mm"].get<double>(),
              2e-3 * report["path_mm"].get<double>());
}

INSTANTIATE_TEST_SUITE_P(
    Kinds, MachinesPipeline,
    ::testing::Values(Case{"cartesian3", "marlin", "csv", "gcode", "; omnislice "},
                      Case{"rotary4", "marlin", "csv", "gcode", "; omnislice "},
                      Case{"rotary4", "reprap", "csv", "gcode", "; omnislice "},
                      Case{"table5", "klipper", "csv", "gcode", "; omnislice "},
                      Case{"table5", "marlin", "csv", "gcode", "; omnislice "},
                      Case{"head5", "reprap", "csv", "gcode", "; omnislice "},
                      Case{"head4", "marlin", "csv", "gcode", "; omnislice "},
                      Case{"robot6-ur5", "marlin", "csv", "csv", "# omnislice "},
                      Case{"robot6-ur5", "marlin", "urscript", "script", "# omnislice "}),
    [](const ::testing::TestParamInfo<Case>& i) {
      std::string n = std::string(i.param.machine) + "_" + i.param.flavor + "_" + i.param.robotFormat;
      for (char& ch : n) {
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
      }
      return n;
    });

// The robot's joint speed limits (paper 003 Table 1: pi/6 rad/s) make the same print slower than on
// a 3-axis printer, and the report's time is the planned one.
TEST(MachinesPipelineTime, RobotLimitsLengthenTheEstimate) {
  const auto bytes = testPart();
  Settings cart = settingsFor({"cartesian3", "marlin", "csv", "", ""});
  Settings robot = settingsFor({"robot6-ur5", "marlin", "csv", "", ""});
  SliceOutput a = runSlice(bytes.data(), bytes.size(), "part.stl", cart);
  SliceOutput b = runSlice(bytes.data(), bytes.size(), "part.stl", robot);
  ASSERT_TRUE(a.ok() && b.ok()) << a.message << b.message;
  const Json ra = Json::parse(a.reportJson), rb = Json::parse(b.reportJson);
  EXPECT_NEAR(ra["path_mm"].get<double>(), rb["path_mm"].get<double>(), 1e-6 * ra["path_mm"].get<double>());
  EXPECT_GE(rb["estimated_time_s"].get<double>(), ra["estimated_time_s"].get<double>());
}

TEST(MachinesPipelineErrors, BadMachineInputIsAStatus) {
  Settings s;
  Outcome o = setSetting(s, "machine", "delta7");
  EXPECT_EQ(o.status, Status::InvalidOption);
  EXPECT_NE(o.message.find("robot6-ur5"), std::string::npos) << o.message;
  EXPECT_EQ(setSetting(s, "machine_json", "{\"kind\":").status, Status::InvalidOption);
  EXPECT_EQ(setSetting(s, "machine_json", "[1,2]").status, Status::InvalidOption);
  EXPECT_EQ(setSetting(s, "gcode_flavor", "sailfish").status, Status::InvalidOption);
  EXPECT_EQ(setSetting(s, "robot_format", "fanuc").status, Status::InvalidOption);
  EXPECT_EQ(setSetting(s, "motion.free_rotation_samples", "0").status, Status::InvalidOption);

  // A user profile of an unknown kind is refused when it is set, with a message naming it.
  o = setSetting(s, "machine_json", "{\"kind\":\"hexapod\"}");
  EXPECT_EQ(o.status, Status::InvalidOption);
  EXPECT_NE(o.message.find("hexapod"), std::string::npos) << o.message;

  // A part far larger than the robot's reach: InvalidOption naming the unreachable move.
  Settings big;
  ASSERT_TRUE(setSetting(big, "machine", "robot6-ur5").ok());
  for (const auto& [k, v] : {std::pair<const char*, const char*>{"layer_height", "0.4"},
                             {"nozzle_diameter", "0.8"}, {"bed_size", "9000,9000,100"},
                             {"infill", "0"}, {"walls", "1"}, {"top_layers", "0"},
                             {"bottom_layers", "0"}}) {
    ASSERT_TRUE(setSetting(big, k, v).ok()) << k;
  }
  // 4 m wide: its corners are farther from the platform centre than the UR5 can bring them to the
  // nozzle, whatever the platform's rotation.
  const auto huge = test::binaryStl(test::makeBox(0, 0, 0, 4000, 4000, 2));
  SliceOutput far = runSlice(huge.data(), huge.size(), "huge.stl", big);
  EXPECT_EQ(far.status, Status::InvalidOption) << far.message;
  EXPECT_NE(far.message.find("reach"), std::string::npos) << far.message;
}

// A user's profile: a rotary4 machine whose A axis is limited to +-30 degrees, given as JSON.
TEST(MachinesPipelineProfile, UserProfileIsUsedAndRecorded) {
  MachineProfileResult base = builtinMachine("rotary4", {220, 220, 250}, 0.4);
  ASSERT_TRUE(base.ok());
  MachineProfile m = base.machine;
  m.name = "my-rotary";
  m.axisLimits["A"] = {-30, 30};
  Settings s;
  ASSERT_TRUE(setSetting(s, "machine_json", machineJson(m)).ok());
  const auto bytes = testPart();
  SliceOutput out = runSlice(bytes.data(), bytes.size(), "part.stl", s);
  ASSERT_TRUE(out.ok()) << out.message;
  const Json report = Json::parse(out.reportJson);
  EXPECT_EQ(report["machine"], "my-rotary");
  EXPECT_EQ(report["machine_profile"]["axis_limits"]["A"][1].get<double>(), 30);
  EXPECT_NE(out.program.find("\"A\":[-30"), std::string::npos);
}

// Firmware axis letters (PROGRAM-FORMAT.md `axis_letters`, e.g. a Duet whose rotary axes are U and
// V): the program with B and C written as U and V is the same print. Its moves are the default
// program's with only those words renamed, the header says so, and the replay and the simulation
// give the same values and figures as the default program's.
TEST(MachinesPipelineAxisLetters, RenamedRotaryAxesReplayToTheSamePrint) {
  const auto bytes = test::binaryStl(test::makeLBracket(10));
  Settings plain;
  for (const auto& [k, v] : {std::pair<const char*, const char*>{"machine", "table5"}, {"method", "multidir"},
                             {"gcode_flavor", "reprap"}}) {
    ASSERT_TRUE(setSetting(plain, k, v).ok()) << k;
  }
  Settings renamed = plain;
  ASSERT_TRUE(setSetting(renamed, "axis_letters", "b=u, C=V").ok());
  const SliceOutput a = runSlice(bytes.data(), bytes.size(), "bracket.stl", plain);
  const SliceOutput b = runSlice(bytes.data(), bytes.size(), "bracket.stl", renamed);
  ASSERT_TRUE(a.ok()) << a.message;
  ASSERT_TRUE(b.ok()) << b.message;
  EXPECT_EQ(Json::parse(b.reportJson)["machine_profile"]["axis_letters"], Json::parse(R"({"B":"U","C":"V"})"));

  auto lines = [](const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) out.push_back(l);
    return out;
  };
  const std::vector<std::string> la = lines(a.program), lb = lines(b.program);
  ASSERT_EQ(la.size(), lb.size());
  size_t moves = 0, tilted = 0, machineLines = 0;
  for (size_t i = 1; i < la.size(); ++i) {  // line 1 has the date (the two may differ by a second)
    if (la[i].rfind("; omnislice:machine ", 0) == 0) {
      ++machineLines;
      EXPECT_NE(lb[i].find("\"axis_letters\":{\"B\":\"U\",\"C\":\"V\"}"), std::string::npos) << lb[i];
      continue;
    }
    if (la[i].rfind("G0 ", 0) != 0 && la[i].rfind("G1 ", 0) != 0) {
      EXPECT_EQ(la[i], lb[i]) << "line " << i + 1;
      continue;
    }
    ++moves;
    std::string expected = la[i];
    for (auto& [from, to] : {std::pair<const char*, const char*>{" B", " U"}, {" C", " V"}}) {
      for (size_t at = expected.find(from); at != std::string::npos; at = expected.find(from, at + 1)) expected.replace(at, 2, to);
    }
    EXPECT_EQ(lb[i], expected) << "line " << i + 1;
    EXPECT_EQ(lb[i].find(" B"), std::string::npos) << lb[i];
    EXPECT_EQ(lb[i].find(" C"), std::string::npos) << lb[i];
    const size_t u = lb[i].find(" U");
    if (u != std::string::npos && std::abs(std::atof(lb[i].c_str() + u + 2)) > 1) ++tilted;
  }
  EXPECT_EQ(machineLines, 1u);
  EXPECT_GT(moves, 100u);
  EXPECT_GT(tilted, 10u) << "the bracket's arm prints tilted: U (the B axis) moves";

  // The reader takes the letters from the header: the same machine values move by move.
  const ParsedProgram pa = readProgram(a.program), pb = readProgram(b.program);
  ASSERT_TRUE(pa.ok()) << pa.message;
  ASSERT_TRUE(pb.ok()) << pb.message;
  ASSERT_EQ(pa.moves.size(), pb.moves.size());
  for (size_t i = 0; i < pa.moves.size(); ++i) {
    ASSERT_EQ(pa.moves[i].axes, pb.moves[i].axes) << "move " << i;
    ASSERT_EQ(pa.moves[i].to, pb.moves[i].to) << "move " << i;
    ASSERT_EQ(pa.moves[i].axis, pb.moves[i].axis) << "move " << i;
    ASSERT_EQ(pa.moves[i].filament, pb.moves[i].filament) << "move " << i;
  }
  // Without the header's letters, U and V are words of no axis: B and C would stay 0.
  std::string stripped = b.program;
  const size_t at = stripped.find(",\"axis_letters\":{\"B\":\"U\",\"C\":\"V\"}");
  ASSERT_NE(at, std::string::npos);
  stripped.erase(at, std::strlen(",\"axis_letters\":{\"B\":\"U\",\"C\":\"V\"}"));
  const ParsedProgram ps = readProgram(stripped);
  ASSERT_TRUE(ps.ok()) << ps.message;
  double maxB = 0, maxBRenamed = 0;
  for (const auto& m : ps.moves) maxB = std::max(maxB, std::abs(m.axes.at(3)));
  for (const auto& m : pb.moves) maxBRenamed = std::max(maxBRenamed, std::abs(m.axes.at(3)));
  EXPECT_EQ(maxB, 0.0);
  EXPECT_GT(maxBRenamed, 1.0);

  // The simulation through the declared machine: the same figures.
  const VerifyOutput va = runVerify(a.program, bytes.data(), bytes.size(), "bracket.stl");
  const VerifyOutput vb = runVerify(b.program, bytes.data(), bytes.size(), "bracket.stl");
  ASSERT_TRUE(va.ok() && vb.ok()) << va.message << vb.message;
  Json ja = Json::parse(va.verifyJson), jb = Json::parse(vb.verifyJson);
  for (const char* key : {"inside", "coverage", "supported", "collisions", "limits", "extrusion_mm", "path_mm", "layers"}) {
    EXPECT_EQ(ja[key], jb[key]) << key;
  }
}

TEST(MachinesPipelineAxisLetters, LettersTheFirmwareCannotTakeAreRefused) {
  const auto bytes = testPart();
  Settings s;
  // Syntax: refused when set.
  for (const char* bad : {"BU", "B=", "=U", "B=U,B=V"}) {
    const Outcome o = setSetting(s, "axis_letters", bad);
    EXPECT_EQ(o.status, Status::InvalidOption) << bad;
    EXPECT_NE(o.message.find("axis_letters"), std::string::npos) << o.message;
  }
  // Against the machine: refused when the machine is resolved, before any slicing.
  const std::pair<const char*, const char*> cases[] = {
      {"table5", "B=E"},       // extrusion's letter
      {"table5", "B=F"},       // feed's
      {"table5", "B=UV"},      // one letter
      {"table5", "B=X"},       // X would be written twice
      {"table5", "A=U"},       // not an axis of table5
      {"rotary4", "C=V"},      // nor of rotary4
      {"robot6-ur5", "B=U"},   // joints have no letters
  };
  for (const auto& [machine, letters] : cases) {
    Settings t;
    ASSERT_TRUE(setSetting(t, "machine", machine).ok());
    ASSERT_TRUE(setSetting(t, "axis_letters", letters).ok()) << letters;
    const SliceOutput out = runSlice(bytes.data(), bytes.size(), "part.stl", t);
    EXPECT_EQ(out.status, Status::InvalidOption) << machine << " " << letters;
    EXPECT_NE(out.message.find("axis letters"), std::string::npos) << out.message;
    EXPECT_TRUE(out.program.empty());
  }
  // Swapping two letters is allowed (each written once): X and Y exchanged on a cartesian3.
  Settings swap;
  ASSERT_TRUE(setSetting(swap, "axis_letters", "X=Y,Y=X").ok());
  const SliceOutput ok = runSlice(bytes.data(), bytes.size(), "part.stl", swap);
  ASSERT_TRUE(ok.ok()) << ok.message;
  const VerifyOutput v = runVerify(ok.program, bytes.data(), bytes.size(), "part.stl");
  ASSERT_TRUE(v.ok()) << v.message;
  EXPECT_GE(Json::parse(v.verifyJson)["inside"].get<double>(), 0.99);
}


// head5 (a 5-axis head over a fixed bed, PROGRAM-FORMAT.md): every method that tilts prints the
// same part-frame tool path as on table5 (the methods see the same tilt range), so the simulation
// through head5's own forward map must give table5's figures; the head's B and C move, and the
// carriage point stands the tip offset away from the tip.
TEST(MachinesPipelineHead5, EveryMethodPrintsAsOnTheTiltingTable) {
  const auto box = testPart();
  const auto bracket = test::binaryStl(test::makeLBracket(10));
  struct Run {
    const char* method;
    const std::vector<uint8_t>* bytes;
  };
  for (const Run& run : {Run{"planar", &box}, Run{"multidir", &bracket}, Run{"geodesic", &bracket}}) {
    SCOPED_TRACE(run.method);
    Json figures[2];
    std::string programs[2];
    for (int k = 0; k < 2; ++k) {
      Settings s;
      ASSERT_TRUE(setSetting(s, "machine", k == 0 ? "table5" : "head5").ok());
      ASSERT_TRUE(setSetting(s, "method", run.method).ok());
      ASSERT_TRUE(setSetting(s, "verify", "warn").ok());
      const SliceOutput out = runSlice(run.bytes->data(), run.bytes->size(), "part.stl", s);
      ASSERT_TRUE(out.ok()) << out.message;
      const VerifyOutput v = runVerify(out.program, run.bytes->data(), run.bytes->size(), "part.stl");
      ASSERT_TRUE(v.ok()) << v.message;
      figures[k] = Json::parse(v.verifyJson);
      programs[k] = out.program;
    }
    const Json& t = figures[0];
    const Json& h = figures[1];
    for (const char* key : {"inside", "coverage", "supported", "surface_reached"}) {
      EXPECT_NEAR(h[key].get<double>(), t[key].get<double>(), 0.003) << key << " " << h.dump();
    }
    EXPECT_EQ(h["collisions"].get<int>(), t["collisions"].get<int>());
    EXPECT_EQ(h["collisions"].get<int>(), 0);
    EXPECT_EQ(h["limits"].get<int>(), 0);
    EXPECT_GE(h["supported"].get<double>(), 0.99);
    EXPECT_EQ(h["layers"], t["layers"]);
    EXPECT_NEAR(h["path_mm"].get<double>(), t["path_mm"].get<double>(), 0.002 * t["path_mm"].get<double>());
    // Read back through head5: B tilts on the curved and 3+2 prints; the carriage point is the tip
    // plus 60 mm along the nozzle axis.
    const ParsedProgram p = readProgram(programs[1]);
    ASSERT_TRUE(p.ok()) << p.message;
    ASSERT_EQ(p.machine.kind, MachineKind::Head5);
    double maxB = 0, worstOffset = 0;
    for (const ProgramMove& m : p.moves) {
      maxB = std::max(maxB, std::abs(m.axes.at(3)));
      const Eigen::Vector3d carriage(m.axes[0], m.axes[1], m.axes[2]);
      worstOffset = std::max(worstOffset, (carriage - (m.to + 60 * m.axis)).norm());
    }
    EXPECT_LT(worstOffset, 1e-3);
    if (std::string(run.method) != "planar") EXPECT_GT(maxB, 10);
  }
}


// The joint targets of a robot program, in program order, as radians of q: CSV rows, RAPID
// MoveAbsJ jointtargets and KRL PTP E6AXIS targets (controller degrees, times the joint sign) read
// from the text directly (not through readProgram); repeated targets once.
std::vector<std::array<double, 6>> jointTargets(const std::string& program, const MachineProfile& m) {
  std::vector<std::array<double, 6>> out;
  std::istringstream in(program);
  std::string line;
  while (std::getline(in, line)) {
    const size_t b = line.find_first_not_of(' ');
    if (b == std::string::npos) continue;
    line = line.substr(b);
    std::array<double, 6> q{};
    if (line.rfind("MoveAbsJ [[", 0) == 0) {
      std::istringstream v(line.substr(11));
      char comma;
      for (int i = 0; i < 6; ++i) {
        v >> q[i];
        if (i < 5) v >> comma;
        q[i] *= m.jointSigns[i] * kPi / 180;
      }
    } else if (line.rfind("PTP {", 0) == 0) {
      for (int i = 0; i < 6; ++i) {
        const size_t at = line.find("A" + std::to_string(i + 1) + " ");
        EXPECT_NE(at, std::string::npos) << line;
        q[i] = std::strtod(line.c_str() + at + 3, nullptr) * m.jointSigns[i] * kPi / 180;
      }
    } else if (line[0] != '#' && std::count(line.begin(), line.end(), ',') == 8) {
      std::istringstream v(line);
      char comma;
      for (int i = 0; i < 6; ++i) {
        v >> q[i];
        v >> comma;
      }
      if (!v) continue;
    } else {
      continue;
    }
    // Filament-only moves (a CSV row without joint change) are not targets.
    if (out.empty() || out.back() != q) out.push_back(q);
  }
  return out;
}

// ABB IRB 1200 and KUKA KR 6 (spherical wrists, their controllers' angles): a box slices on each,
// the RAPID and KRL programs carry the joint CSV's targets (degrees in the controller's zero and
// senses), read back to the same print and verify as the CSV does: sound.
TEST(MachinesPipelineIndustrialArms, RapidAndKrlCarryTheCsvJointsAndVerify) {
  const auto box = testPart();
  struct Run {
    const char* machine;
    const char* format;
    const char* extension;
    const char* parsedFormat;
  };
  for (const Run& run : {Run{"robot6-irb1200", "rapid", "mod", "rapid"}, Run{"robot6-kr6", "krl", "src", "krl"}}) {
    SCOPED_TRACE(run.machine);
    Json figures[2];
    std::string programs[2];
    double times[2] = {0, 0};
    for (int k = 0; k < 2; ++k) {
      Settings s;
      ASSERT_TRUE(setSetting(s, "machine", run.machine).ok());
      ASSERT_TRUE(setSetting(s, "robot_format", k == 0 ? "csv" : run.format).ok());
      ASSERT_TRUE(setSetting(s, "layer_height", "0.4").ok());
      const SliceOutput out = runSlice(box.data(), box.size(), "part.stl", s);
      ASSERT_TRUE(out.ok()) << out.message;
      EXPECT_EQ(out.programExtension, k == 0 ? "csv" : run.extension);
      const VerifyOutput v = runVerify(out.program, box.data(), box.size(), "part.stl");
      ASSERT_TRUE(v.ok()) << v.message;
      figures[k] = Json::parse(v.verifyJson);
      programs[k] = out.program;
      times[k] = Json::parse(out.reportJson)["estimated_time_s"].get<double>();
    }
    const MachineProfile m = builtinMachine(run.machine, Eigen::Vector3d(200, 200, 200), 0.4).machine;
    const auto csv = jointTargets(programs[0], m);
    const auto own = jointTargets(programs[1], m);
    ASSERT_GT(csv.size(), 100u);
    ASSERT_EQ(own.size(), csv.size());
    double worst = 0;
    for (size_t i = 0; i < csv.size(); ++i) {
      for (int j = 0; j < 6; ++j) worst = std::max(worst, std::abs(own[i][j] - csv[i][j]));
    }
    // 6 decimals of a degree: half a micro-degree, 8.7e-9 rad.
    EXPECT_LT(worst, 1e-8) << "joint values differ from the CSV's by " << worst << " rad";
    const ParsedProgram p = readProgram(programs[1]);
    ASSERT_TRUE(p.ok()) << p.message;
    EXPECT_EQ(p.format, run.parsedFormat);
    EXPECT_EQ(p.machine.jointSigns, m.jointSigns);
    const Json& c = figures[0];
    const Json& o = figures[1];
    for (const char* key : {"inside", "coverage", "supported", "surface_reached"}) {
      EXPECT_NEAR(o[key].get<double>(), c[key].get<double>(), 1e-3) << key << " " << o.dump();
    }
    EXPECT_NEAR(o["path_mm"].get<double>(), c["path_mm"].get<double>(), 1e-3 * c["path_mm"].get<double>());
    EXPECT_EQ(o["collisions"].get<int>(), 0);
    EXPECT_EQ(o["limits"].get<int>(), 0);
    EXPECT_GE(o["supported"].get<double>(), 0.99);
    EXPECT_GE(o["inside"].get<double>(), 0.99);
    // KRL moves at whole percentages of the axis speeds, never faster than planned: its time is at
    // least the plan's; RAPID's \T times are the plan's.
    if (std::string(run.format) == "krl") {
      EXPECT_GE(times[1], times[0] * 0.999);
    } else {
      EXPECT_NEAR(times[1], times[0], 1e-6 * times[0]);
    }
    std::printf("%s %s: %zu targets, worst joint difference %.2g rad, time %.0f s (CSV %.0f s), "
                "supported %.4f, collisions %d\n",
                run.machine, run.format, own.size(), worst, times[1], times[0], o["supported"].get<double>(),
                o["collisions"].get<int>());
  }
}

// head4 (a nozzle leaning a fixed 45 degrees, turned by C): planar layers keep table5's path with
// the nozzle at the head's tilt, 3+2 parts are cut within its 45-degree reach; the cone clears the
// layer being printed (45 > 40 degrees), so the simulation finds both sound, and every move's axis
// in the read-back program leans exactly 45 degrees.
TEST(MachinesPipelineHead4, PlanarAndMultidirPrintSoundlyWithTheTiltedNozzle) {
  const auto box = testPart();
  const auto bracket = test::binaryStl(test::makeLBracket(10));
  for (const auto& [method, bytes] : {std::pair<const char*, const std::vector<uint8_t>*>{"planar", &box}, {"multidir", &bracket}}) {
    SCOPED_TRACE(method);
    Json figures[2];
    std::string program;
    for (int k = 0; k < 2; ++k) {
      Settings s;
      ASSERT_TRUE(setSetting(s, "machine", k == 0 ? "table5" : "head4").ok());
      ASSERT_TRUE(setSetting(s, "method", method).ok());
      const SliceOutput out = runSlice(bytes->data(), bytes->size(), "part.stl", s);
      ASSERT_TRUE(out.ok()) << out.message;
      const VerifyOutput v = runVerify(out.program, bytes->data(), bytes->size(), "part.stl");
      ASSERT_TRUE(v.ok()) << v.message;
      figures[k] = Json::parse(v.verifyJson);
      if (k == 1) program = out.program;
    }
    const Json& t = figures[0];
    const Json& h = figures[1];
    EXPECT_GE(h["inside"].get<double>(), 0.99);
    EXPECT_GE(h["supported"].get<double>(), 0.99);
    EXPECT_GE(h["surface_reached"].get<double>(), 0.99);
    EXPECT_EQ(h["collisions"].get<int>(), 0);
    EXPECT_EQ(h["limits"].get<int>(), 0);
    if (std::string(method) == "planar") {
      // The same layers: the same path and support (multidir's search sees head4's 45-degree
      // tilt limit, not table5's 90, so it cuts other parts).
      EXPECT_NEAR(h["supported"].get<double>(), t["supported"].get<double>(), 0.003);
      EXPECT_NEAR(h["path_mm"].get<double>(), t["path_mm"].get<double>(), 0.002 * t["path_mm"].get<double>());
    }
    const ParsedProgram p = readProgram(program);
    ASSERT_TRUE(p.ok()) << p.message;
    ASSERT_EQ(p.machine.kind, MachineKind::Head4);
    double worstTilt = 0;
    for (const ProgramMove& m : p.moves) worstTilt = std::max(worstTilt, std::abs(std::acos(m.axis.z()) * 180 / M_PI - 45));
    EXPECT_LT(worstTilt, 1e-6);
  }
}

}  // namespace
}  // namespace omnislice
