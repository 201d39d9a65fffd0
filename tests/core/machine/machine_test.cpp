// SPDX-License-Identifier: MIT
// Machine profiles: built-in values, the JSON round trip of every built-in (profile -> JSON ->
// profile -> JSON identical, every field equal), malformed inputs (ParseError with a message,
// never a crash, also on a few hundred mutated strings).
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <random>
#include <string>

#include "common/math_constants.h"
#include "kinematics/kinematics.h"
#include "kinematics/robot_arm.h"
#include "machine/machine.h"
#include "program/interpolate_machine_move.h"
#include "machine/machine_json.h"

namespace omnislice {
namespace {

const Eigen::Vector3d kBed{220, 200, 250};

void expectSameDynamics(const AxisDynamics& a, const AxisDynamics& b) {
  EXPECT_EQ(a.velocity, b.velocity);
  EXPECT_EQ(a.acceleration, b.acceleration);
  EXPECT_EQ(a.jerk, b.jerk);
}

void expectSameProfile(const MachineProfile& a, const MachineProfile& b) {
  EXPECT_EQ(a.kind, b.kind);
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.pivot, b.pivot);
  EXPECT_EQ(a.axisLimits, b.axisLimits);
  ASSERT_EQ(a.axisDynamics.size(), b.axisDynamics.size());
  for (const auto& kv : a.axisDynamics) expectSameDynamics(kv.second, b.axisDynamics.at(kv.first));
  EXPECT_EQ(a.stepAngleDegrees, b.stepAngleDegrees);
  EXPECT_EQ(a.safeZ, b.safeZ);
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(a.dh[i].thetaOffset, b.dh[i].thetaOffset);
    EXPECT_EQ(a.dh[i].d, b.dh[i].d);
    EXPECT_EQ(a.dh[i].a, b.dh[i].a);
    EXPECT_EQ(a.dh[i].alpha, b.dh[i].alpha);
    EXPECT_EQ(a.jointLimits[i], b.jointLimits[i]);
    expectSameDynamics(a.jointDynamics[i], b.jointDynamics[i]);
  }
  EXPECT_EQ(a.flangeToPlatform, b.flangeToPlatform);
  EXPECT_EQ(a.nozzleTip, b.nozzleTip);
  EXPECT_EQ(a.nozzleAxis, b.nozzleAxis);
  EXPECT_EQ(a.nozzle.diameter, b.nozzle.diameter);
  EXPECT_EQ(a.nozzle.coneHalfAngleDegrees, b.nozzle.coneHalfAngleDegrees);
  EXPECT_EQ(a.nozzle.coneLength, b.nozzle.coneLength);
  EXPECT_EQ(a.nozzle.carriageSize, b.nozzle.carriageSize);
}

TEST(MachineProfile, BuiltinNamesAndValues) {
  const std::vector<std::string> names = builtinMachineNames();
  ASSERT_EQ(names, (std::vector<std::string>{"cartesian3", "rotary4", "table5", "head4", "head5", "robot6-ur5",
                                                          "robot6-ur5-rated", "robot6-irb1200", "robot6-kr6"}));
  for (const std::string& n : names) {
    const MachineProfileResult r = builtinMachine(n, kBed, 0.6);
    ASSERT_TRUE(r.ok()) << r.message;
    EXPECT_EQ(r.machine.name, n);
    EXPECT_EQ(r.machine.nozzle.diameter, 0.6);
    EXPECT_EQ(machineAxisCount(r.machine.kind), int(machineAxisNames(r.machine.kind).size()));
    EXPECT_EQ(machineAxisLetters(r.machine.kind).size(), r.machine.kind == MachineKind::Robot6 ? 0u : machineAxisNames(r.machine.kind).size());
  }
  const MachineProfile c = builtinMachine("cartesian3", kBed, 0.4).machine;
  EXPECT_EQ(c.axisLimits.at("X"), std::make_pair(-110.0, 110.0));
  EXPECT_EQ(c.axisLimits.at("Z"), std::make_pair(0.0, 250.0));
  EXPECT_EQ(c.axisDynamics.at("X").velocity, 200);

  const MachineProfile r4 = builtinMachine("rotary4", kBed, 0.4).machine;
  EXPECT_EQ(r4.kind, MachineKind::Rotary4);
  EXPECT_EQ(r4.pivot, Eigen::Vector3d::Zero());
  EXPECT_EQ(r4.axisLimits.at("A"), std::make_pair(-60.0, 60.0));
  EXPECT_EQ(r4.axisLimits.at("Y"), std::make_pair(-100.0, 100.0));
  EXPECT_EQ(r4.axisLimits.at("Z"), std::make_pair(-125.0, 250.0));  // tilted parts go below z = 0
  EXPECT_EQ(r4.stepAngleDegrees, 0);
  EXPECT_EQ(r4.axisDynamics.at("A").velocity, 90);
  EXPECT_EQ(r4.axisDynamics.at("A").acceleration, 900);
  EXPECT_EQ(r4.axisDynamics.at("Z").velocity, 20);

  const MachineProfile t5 = builtinMachine("table5", kBed, 0.4).machine;
  EXPECT_EQ(t5.axisLimits.at("B"), std::make_pair(-90.0, 90.0));
  EXPECT_EQ(t5.axisLimits.at("C"), std::make_pair(-3600.0, 3600.0));

  const MachineProfile ur = builtinMachine("robot6", kBed, 1.0).machine;
  EXPECT_EQ(ur.kind, MachineKind::Robot6);
  EXPECT_EQ(ur.name, "robot6-ur5");
  EXPECT_TRUE(isUrFamily(ur.dh));
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(ur.dh[i].d, ur5DhTable()[i].d);
    EXPECT_EQ(ur.dh[i].a, ur5DhTable()[i].a);
    EXPECT_EQ(ur.jointLimits[i], std::make_pair(-2 * kPi, 2 * kPi));
    // Paper 003 Table 1.
    EXPECT_DOUBLE_EQ(ur.jointDynamics[i].velocity, kPi / 6);
    EXPECT_DOUBLE_EQ(ur.jointDynamics[i].acceleration, kPi / 2);
    EXPECT_DOUBLE_EQ(ur.jointDynamics[i].jerk, kPi);
  }
  EXPECT_DOUBLE_EQ(ur.nozzleAxis.norm(), 1.0);
  // The rated arm: the same kinematics, the datasheet's 180 deg/s, 5 rad/s^2, no jerk limit.
  const MachineProfile rated = builtinMachine("robot6-ur5-rated", kBed, 1.0).machine;
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(rated.dh[i].d, ur.dh[i].d);
    EXPECT_EQ(rated.dh[i].a, ur.dh[i].a);
    EXPECT_EQ(rated.dh[i].alpha, ur.dh[i].alpha);
    EXPECT_EQ(rated.jointLimits[i], ur.jointLimits[i]);
    EXPECT_DOUBLE_EQ(rated.jointDynamics[i].velocity, kPi);
    EXPECT_DOUBLE_EQ(rated.jointDynamics[i].acceleration, 5);
    EXPECT_EQ(rated.jointDynamics[i].jerk, 0);
  }
  EXPECT_EQ(rated.nozzleTip, ur.nozzleTip);
  EXPECT_EQ(rated.flangeToPlatform, ur.flangeToPlatform);

  const MachineProfileResult bad = builtinMachine("delta", kBed, 0.4);
  EXPECT_EQ(bad.status, Status::InvalidOption);
  EXPECT_NE(bad.message.find("robot6-ur5"), std::string::npos);
  EXPECT_EQ(builtinMachine("table5", kBed, -1).status, Status::InvalidOption);
  EXPECT_EQ(builtinMachine("table5", {0, 1, 1}, 0.4).status, Status::InvalidOption);
}

TEST(MachineProfile, EveryBuiltinRoundTripsThroughJson) {
  for (const std::string& n : builtinMachineNames()) {
    MachineProfile m = builtinMachine(n, kBed, 0.4).machine;
    if (n == "rotary4") m.stepAngleDegrees = 1.8;  // optional fields too
    if (n == "table5") {
      m.safeZ = 42.5;
      m.nozzle.carriageSize = {70, 50, 30};
    }
    const std::string j1 = machineJson(m);
    EXPECT_EQ(j1.find('\n'), std::string::npos);
    EXPECT_EQ(j1.rfind("{\"kind\":\"" + std::string(machineKindName(m.kind)) + "\"", 0), 0u) << j1;  // kind first
    const MachineParseResult back = machineFromJson(j1);
    ASSERT_TRUE(back.ok()) << back.message << "\n" << j1;
    expectSameProfile(m, back.machine);
    EXPECT_EQ(machineJson(back.machine), j1);
  }
  const std::string ur = machineJson(builtinMachine("robot6-ur5", kBed, 0.4).machine);
  for (const char* key : {"\"dh\":[[", "\"joint_limits\":[[", "\"joint_dynamics\":[{",
                          "\"flange_to_platform\":[", "\"nozzle_tip\":[", "\"nozzle_axis\":[",
                          "\"name\":\"robot6-ur5\""}) {
    EXPECT_NE(ur.find(key), std::string::npos) << key;
  }
  const std::string t5 = machineJson(builtinMachine("table5", kBed, 0.4).machine);
  EXPECT_NE(t5.find("\"dynamics\":{\"X\":{\"velocity\":200.0,\"acceleration\":3000.0"),
            std::string::npos)
      << t5;
  EXPECT_NE(t5.find("\"pivot\":[0.0,0.0,0.0]"), std::string::npos) << t5;
}

TEST(MachineProfile, ParsedRobotDrivesTheKinematics) {
  // A user's robot profile with a theta offset and a tilted plate: IK of the parsed profile still
  // round-trips through FK.
  MachineProfile m = builtinMachine("robot6", kBed, 0.4).machine;
  m.name = "my-ur5";
  m.dh[3].thetaOffset = 0.25;
  Eigen::Matrix3d rot;
  rot = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  m.flangeToPlatform.topLeftCorner<3, 3>() = rot;
  m.nozzleAxis = Eigen::Vector3d(0.1, 0, 1).normalized();
  const MachineParseResult p = machineFromJson(machineJson(m));
  ASSERT_TRUE(p.ok()) << p.message;
  const Eigen::Vector3d tip(10, -20, 30), axis = Eigen::Vector3d(0.2, 0.1, 1).normalized();
  const IkResult ik = inverseMap(p.machine, tip, axis);
  ASSERT_TRUE(ik.ok());
  ASSERT_FALSE(ik.candidates.empty());
  for (const IkCandidate& c : ik.candidates) {
    Eigen::Vector3d t, u;
    ASSERT_TRUE(forwardMap(p.machine, c.values, t, u));
    EXPECT_LT((t - tip).norm(), 1e-6);
    EXPECT_LT((u - axis).norm(), 1e-6);
  }
}

// The writers' length-only walk gives interpolateMachineMove's length to the bit (the robot feed
// f must be what the reader replays), on random moves of every rotating machine, small and large.
TEST(MachineProfile, TipLengthWalkEqualsTheInterpolatedLength) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1, 1);
  size_t multiPiece = 0;
  for (const char* name : {"rotary4", "table5", "robot6-ur5"}) {
    const MachineProfile m = builtinMachine(name, kBed, 0.4).machine;
    const int n = machineAxisCount(m.kind);
    for (int k = 0; k < 300; ++k) {
      MachineValues a{}, b{};
      const double scale = k % 3 == 0 ? 0.01 : k % 3 == 1 ? 0.3 : 1.5;  // rad, or x 57 for degrees
      for (int i = 0; i < n; ++i) {
        const double s = isAngularAxis(m.kind, i) ? (m.kind == MachineKind::Robot6 ? 1.0 : 57.3) : 40.0;
        a[i] = s * unit(rng);
        b[i] = a[i] + s * scale * unit(rng);
      }
      const MoveInterpolation full = interpolateMachineMove(m, a, b);
      ASSERT_TRUE(full.ok()) << full.message;
      Eigen::Vector3d ta, xa, tb, xb;
      ASSERT_TRUE(forwardMap(m, a, ta, xa));
      ASSERT_TRUE(forwardMap(m, b, tb, xb));
      EXPECT_EQ(interpolatedTipLength(m, a, b, ta, xa, tb, xb), full.length) << name << " " << k;
      multiPiece += full.t.size() > 2 ? 1 : 0;
    }
  }
  EXPECT_GT(multiPiece, 300u);  // most moves were bisected
}

// axis_letters (PROGRAM-FORMAT.md): written in the kind's axis order, read back to the same map,
// and the letters G-code uses follow it.
TEST(MachineProfile, AxisLettersRoundTripAndRenameTheWrittenAxes) {
  MachineProfile m = builtinMachine("table5", kBed, 0.4).machine;
  EXPECT_EQ(gcodeAxisLetters(m), (std::vector<std::string>{"X", "Y", "Z", "B", "C"}));
  EXPECT_EQ(machineJson(m).find("axis_letters"), std::string::npos) << "written only when set";
  m.axisLetters = {{"C", "V"}, {"B", "U"}};
  const std::string json = machineJson(m);
  EXPECT_NE(json.find("\"axis_letters\":{\"B\":\"U\",\"C\":\"V\"}"), std::string::npos) << json;
  const MachineParseResult back = machineFromJson(json);
  ASSERT_TRUE(back.ok()) << back.message;
  EXPECT_EQ(back.machine.axisLetters, m.axisLetters);
  EXPECT_EQ(machineJson(back.machine), json);
  EXPECT_EQ(gcodeAxisLetters(back.machine), (std::vector<std::string>{"X", "Y", "Z", "U", "V"}));
  // A robot has joints, not letters.
  MachineProfile ur = builtinMachine("robot6-ur5", kBed, 0.4).machine;
  EXPECT_TRUE(gcodeAxisLetters(ur).empty());
  EXPECT_EQ(checkAxisLetters(MachineKind::Robot6, {{"B", "U"}}).status, Status::InvalidOption);
  EXPECT_TRUE(checkAxisLetters(MachineKind::Rotary4, {{"A", "W"}, {"X", "D"}}).ok());
}

TEST(MachineProfile, MalformedJsonGivesParseError) {
  const std::string ur = machineJson(builtinMachine("robot6-ur5", kBed, 0.4).machine);
  const std::vector<std::string> bad{
      "",
      "[]",
      "{}",
      "{\"kind\":3}",
      "{\"kind\":\"table5\",\"pivot\":[0,0]}",
      "{\"kind\":\"table5\",\"pivot\":[0,0,\"x\"]}",
      "{\"kind\":\"table5\",\"axis_limits\":[]}",
      "{\"kind\":\"table5\",\"axis_limits\":{\"B\":[90,-90]}}",
      "{\"kind\":\"table5\",\"axis_limits\":{\"B\":[1e999,2]}}",
      "{\"kind\":\"table5\",\"dynamics\":{\"X\":{\"velocity\":-1}}}",
      "{\"kind\":\"table5\",\"dynamics\":{\"X\":5}}",
      "{\"kind\":\"rotary4\",\"step_angle_deg\":-2}",
      "{\"kind\":\"rotary4\",\"safe_z\":\"high\"}",
      "{\"kind\":\"cartesian3\",\"nozzle\":{\"diameter\":0}}",
      "{\"kind\":\"cartesian3\",\"nozzle\":{\"cone_half_angle_deg\":95}}",
      "{\"kind\":\"cartesian3\",\"nozzle\":{\"carriage_size\":[1,2]}}",
      "{\"kind\":\"cartesian3\",\"name\":7}",
      "{\"kind\":\"robot6\"}",
      "{\"kind\":\"robot6\",\"dh\":[[0,1,2,3]]}",
      "{\"kind\":\"table5\",\"axis_letters\":[\"U\"]}",
      "{\"kind\":\"table5\",\"axis_letters\":{\"B\":7}}",
      "{\"kind\":\"table5\",\"axis_letters\":{\"B\":\"E\"}}",
      "{\"kind\":\"table5\",\"axis_letters\":{\"B\":\"C\"}}",
      "{\"kind\":\"table5\",\"axis_letters\":{\"A\":\"U\"}}",
      "{\"kind\":\"cartesian3\",\"axis_letters\":{\"X\":\"x\"}}",
      "{\"kind\":\"robot6\",\"dh\":[[0,1,2,3],[0,1,2,3],[0,1,2,3],[0,1,2,3],[0,1,2,3],[0,1,2]]}",
  };
  for (const std::string& s : bad) {
    const MachineParseResult r = machineFromJson(s);
    EXPECT_EQ(r.status, Status::ParseError) << s;
    EXPECT_FALSE(r.message.empty()) << s;
  }
  // Robot keys replaced one at a time in the valid UR5 profile.
  auto replaced = [&](const std::string& key, const std::string& value) {
    const size_t at = ur.find("\"" + key + "\":");
    EXPECT_NE(at, std::string::npos);
    const size_t start = at + key.size() + 3;
    // Every robot value is an array: it ends at its matching ']'.
    int depth = 0;
    size_t end = start;
    do {
      if (ur[end] == '[' || ur[end] == '{') ++depth;
      if (ur[end] == ']' || ur[end] == '}') --depth;
      ++end;
    } while (depth > 0 && end < ur.size());
    return ur.substr(0, start) + value + ur.substr(end);
  };
  const std::vector<std::pair<std::string, std::string>> robotBad{
      {"flange_to_platform", "[2,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1]"},  // not rigid (scaled)
      {"flange_to_platform", "[1,0,0,0,0,1,0,0,0,0,-1,0,0,0,0,1]"},  // reflection
      {"flange_to_platform", "[1,0,0,0,0,1,0,0,0,0,1,0,1,0,0,1]"},   // bottom row
      {"flange_to_platform", "[1,0,0]"},
      {"nozzle_axis", "[0,0,0]"},
      {"nozzle_tip", "[0,0]"},
      {"joint_limits", "[[1,0],[0,1],[0,1],[0,1],[0,1],[0,1]]"},
      {"joint_limits", "[[0,1]]"},
      {"joint_dynamics", "[{},{},{},{},{},{\"jerk\":-1}]"},
      {"dh", "[[0,1,2,3],[0,1,2,3],[0,1,2,3],[0,1,2,3],[0,1,2,3],[0,1,2,null]]"},
  };
  for (const auto& kv : robotBad) {
    const std::string s = replaced(kv.first, kv.second);
    const MachineParseResult r = machineFromJson(s);
    EXPECT_EQ(r.status, Status::ParseError) << s;
    EXPECT_FALSE(r.message.empty());
  }
  // The replacement helper itself produces valid JSON for valid values.
  EXPECT_TRUE(machineFromJson(replaced("nozzle_axis", "[0,0,2]")).ok());
  EXPECT_EQ(machineFromJson(replaced("nozzle_axis", "[0,0,2]")).machine.nozzleAxis,
            Eigen::Vector3d::UnitZ());
  // Missing cone keys keep the defaults; extra keys are accepted; the name defaults to the kind.
  const MachineParseResult d =
      machineFromJson("{\"kind\":\"rotary4\",\"extra\":1,\"nozzle\":{\"diameter\":0.5}}");
  ASSERT_TRUE(d.ok()) << d.message;
  EXPECT_EQ(d.machine.nozzle.coneHalfAngleDegrees, 40);
  EXPECT_EQ(d.machine.nozzle.coneLength, 25);
  EXPECT_EQ(d.machine.kind, MachineKind::Rotary4);
  EXPECT_EQ(d.machine.name, "rotary4");
  // A kind this build does not know (a newer build's machine) is UnsupportedFormat, naming it.
  const MachineParseResult delta = machineFromJson("{\"kind\":\"delta\",\"nozzle\":{\"diameter\":0.5}}");
  EXPECT_EQ(delta.status, Status::UnsupportedFormat);
  EXPECT_NE(delta.message.find("delta"), std::string::npos) << delta.message;
  // The minimal user profile of docs/MACHINES.md.
  const MachineParseResult u = machineFromJson(
      R"({"kind":"table5","pivot":[0,0,-30],"axis_limits":{"X":[-100,100],"Y":[-100,100],)"
      R"("Z":[-80,200],"B":[-120,120],"C":[-720,720]},"nozzle":{"diameter":0.6}})");
  ASSERT_TRUE(u.ok()) << u.message;
  EXPECT_EQ(u.machine.pivot, Eigen::Vector3d(0, 0, -30));
  EXPECT_EQ(u.machine.axisLimits.at("C"), std::make_pair(-720.0, 720.0));
  EXPECT_EQ(u.machine.nozzle.diameter, 0.6);
  EXPECT_EQ(u.machine.nozzle.carriageSize, Eigen::Vector3d(60, 60, 40));
}

// Mutated profiles (bytes deleted, replaced, duplicated, truncated) never crash: either a valid
// profile or ParseError with a message.
TEST(MachineProfile, FuzzedJsonNeverCrashes) {
  std::mt19937 rng(21);
  const char alphabet[] = "{}[],:\"0123456789.-eE+ nulltruefalse";
  int parsed = 0, rejected = 0;
  for (const std::string& n : builtinMachineNames()) {
    const std::string base = machineJson(builtinMachine(n, kBed, 0.4).machine);
    for (int i = 0; i < 150; ++i) {
      std::string s = base;
      const int edits = 1 + static_cast<int>(rng() % 4);
      for (int e = 0; e < edits && !s.empty(); ++e) {
        const size_t at = rng() % s.size();
        switch (rng() % 4) {
          case 0: s.erase(at, 1 + rng() % 8); break;
          case 1: s[at] = alphabet[rng() % (sizeof(alphabet) - 1)]; break;
          case 2: s.insert(at, s.substr(at, 1 + rng() % 12)); break;
          default: s.resize(at); break;
        }
      }
      const MachineParseResult r = machineFromJson(s);
      if (r.ok()) {
        ++parsed;
        // Whatever parsed is a consistent profile that writes and parses again identically.
        const std::string again = machineJson(r.machine);
        const MachineParseResult r2 = machineFromJson(again);
        ASSERT_TRUE(r2.ok()) << again;
        EXPECT_EQ(machineJson(r2.machine), again);
      } else {
        ++rejected;
        // A kind the edits turned into an unknown name (e.g. "head") is a newer build's machine.
        EXPECT_TRUE(r.status == Status::ParseError || r.status == Status::UnsupportedFormat) << s;
        EXPECT_FALSE(r.message.empty());
      }
    }
  }
  EXPECT_GT(rejected, 300);
  EXPECT_EQ(parsed + rejected, 150 * static_cast<int>(builtinMachineNames().size()));
}

}  // namespace
}  // namespace omnislice
