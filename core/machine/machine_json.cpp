// SPDX-License-Identifier: MIT
#include "machine/machine_json.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

namespace omnislice {

namespace {
using OJson = nlohmann::ordered_json;

// Letters of the kind in their natural order, then any others of `keys` alphabetically.
template <typename Map>
std::vector<std::string> letterOrder(MachineKind kind, const Map& keys) {
  std::vector<std::string> order = machineAxisLetters(kind);
  for (const auto& kv : keys) {
    if (std::find(order.begin(), order.end(), kv.first) == order.end()) order.push_back(kv.first);
  }
  return order;
}

OJson dynamicsJson(const AxisDynamics& d) {
  return OJson{{"velocity", d.velocity}, {"acceleration", d.acceleration}, {"jerk", d.jerk}};
}

const NozzleGeometry kDefaultNozzle{};
}  // namespace

std::string machineJson(const MachineProfile& machine) {
  // ordered_json keeps the key order of the format page (kind first). Optional keys are written
  // when they differ from their defaults (docs/MACHINES.md), so the planar header stays short.
  OJson j;
  j["kind"] = machineKindName(machine.kind);
  if (machine.name != machineKindName(machine.kind)) j["name"] = machine.name;
  const bool pivoting = machine.kind == MachineKind::Rotary4 || machine.kind == MachineKind::Table5;
  if (pivoting || !machine.pivot.isZero(0)) {
    j["pivot"] = {machine.pivot.x(), machine.pivot.y(), machine.pivot.z()};
  }
  if (!machine.axisLimits.empty() || machine.kind != MachineKind::Robot6) {
    OJson limits = OJson::object();
    for (const std::string& axis : letterOrder(machine.kind, machine.axisLimits)) {
      auto it = machine.axisLimits.find(axis);
      if (it != machine.axisLimits.end()) limits[axis] = {it->second.first, it->second.second};
    }
    j["axis_limits"] = limits;
  }
  if (!machine.axisDynamics.empty()) {
    OJson dyn = OJson::object();
    for (const std::string& axis : letterOrder(machine.kind, machine.axisDynamics)) {
      auto it = machine.axisDynamics.find(axis);
      if (it != machine.axisDynamics.end()) dyn[axis] = dynamicsJson(it->second);
    }
    j["dynamics"] = dyn;
  }
  if (machine.kind == MachineKind::Head4) j["tilt_deg"] = machine.tiltDegrees;
  if (machine.kind == MachineKind::Head5 || machine.kind == MachineKind::Head4 || !machine.tipOffset.isZero(0)) {
    j["tip_offset"] = {machine.tipOffset.x(), machine.tipOffset.y(), machine.tipOffset.z()};
  }
  if (machine.stepAngleDegrees != 0) j["step_angle_deg"] = machine.stepAngleDegrees;
  if (machine.safeZ != 0) j["safe_z"] = machine.safeZ;
  if (!machine.axisLetters.empty()) {
    OJson letters = OJson::object();
    for (const std::string& axis : letterOrder(machine.kind, machine.axisLetters)) {
      auto it = machine.axisLetters.find(axis);
      if (it != machine.axisLetters.end()) letters[axis] = it->second;
    }
    j["axis_letters"] = letters;
  }
  if (machine.kind == MachineKind::Robot6) {
    OJson dh = OJson::array();
    for (const DhRow& r : machine.dh) dh.push_back({r.thetaOffset, r.d, r.a, r.alpha});
    j["dh"] = dh;
    OJson limits = OJson::array();
    for (const auto& l : machine.jointLimits) limits.push_back({l.first, l.second});
    j["joint_limits"] = limits;
    OJson dyn = OJson::array();
    for (const AxisDynamics& d : machine.jointDynamics) dyn.push_back(dynamicsJson(d));
    j["joint_dynamics"] = dyn;
    OJson t = OJson::array();
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) t.push_back(machine.flangeToPlatform(r, c));
    }
    j["flange_to_platform"] = t;
    j["nozzle_tip"] = {machine.nozzleTip.x(), machine.nozzleTip.y(), machine.nozzleTip.z()};
    j["nozzle_axis"] = {machine.nozzleAxis.x(), machine.nozzleAxis.y(), machine.nozzleAxis.z()};
    if (machine.jointSigns != std::array<int, 6>{1, 1, 1, 1, 1, 1}) {
      OJson signs = OJson::array();
      for (int sign : machine.jointSigns) signs.push_back(sign);
      j["joint_signs"] = signs;
    }
    if (machine.ikBranches != 0xff) j["ik_branches"] = machine.ikBranches;
  }
  OJson nozzle = {{"diameter", machine.nozzle.diameter},
                  {"cone_half_angle_deg", machine.nozzle.coneHalfAngleDegrees},
                  {"cone_length", machine.nozzle.coneLength}};
  if (machine.nozzle.carriageSize != kDefaultNozzle.carriageSize) {
    const Eigen::Vector3d& c = machine.nozzle.carriageSize;
    nozzle["carriage_size"] = {c.x(), c.y(), c.z()};
  }
  j["nozzle"] = nozzle;
  return j.dump();
}

namespace {
using Json = nlohmann::json;

bool finiteNumber(const Json& v) { return v.is_number() && std::isfinite(v.get<double>()); }

// Reads an array of n finite numbers.
bool readNumbers(const Json& v, size_t n, double* out) {
  if (!v.is_array() || v.size() != n) return false;
  for (size_t i = 0; i < n; ++i) {
    if (!finiteNumber(v[i])) return false;
    out[i] = v[i].get<double>();
  }
  return true;
}

// {"velocity":..,"acceleration":..,"jerk":..}, each optional, finite and >= 0.
bool readDynamics(const Json& v, AxisDynamics& d) {
  if (!v.is_object()) return false;
  const std::pair<const char*, double*> keys[3] = {
      {"velocity", &d.velocity}, {"acceleration", &d.acceleration}, {"jerk", &d.jerk}};
  for (const auto& k : keys) {
    auto it = v.find(k.first);
    if (it == v.end()) continue;
    if (!finiteNumber(*it) || it->get<double>() < 0) return false;
    *k.second = it->get<double>();
  }
  return true;
}

struct Parser {
  MachineParseResult r;
  bool failed = false;
  void fail(const std::string& msg) {
    if (failed) return;
    failed = true;
    r.status = Status::ParseError;
    r.message = "machine JSON: " + msg;
  }

  void parse(const Json& j) {
    MachineProfile& m = r.machine;
    if (!j.is_object()) return fail("not a JSON object");
    auto kind = j.find("kind");
    if (kind == j.end() || !kind->is_string()) return fail("missing \"kind\"");
    const std::string kindName = kind->get<std::string>();
    if (!parseMachineKind(kindName, m.kind)) {
      fail("kind \"" + kindName.substr(0, 40) +
           "\" is not one of cartesian3, rotary4, table5, head4, head5, robot6: this build cannot use or replay it");
      r.status = Status::UnsupportedFormat;
      return;
    }
    m.name = kindName;
    if (auto it = j.find("name"); it != j.end()) {
      if (!it->is_string()) return fail("\"name\" must be a string");
      m.name = it->get<std::string>();
    }
    if (auto it = j.find("pivot"); it != j.end()) {
      double p[3];
      if (!readNumbers(*it, 3, p)) return fail("\"pivot\" must be 3 finite numbers");
      m.pivot = {p[0], p[1], p[2]};
    }
    if (auto it = j.find("axis_limits"); it != j.end()) {
      if (!it->is_object()) return fail("\"axis_limits\" must be an object");
      for (auto a = it->begin(); a != it->end(); ++a) {
        double l[2];
        if (!readNumbers(a.value(), 2, l)) {
          return fail("limit of axis " + a.key() + " must be [min, max] finite numbers");
        }
        if (l[0] > l[1]) return fail("limit of axis " + a.key() + " has min > max");
        m.axisLimits[a.key()] = {l[0], l[1]};
      }
    }
    if (auto it = j.find("dynamics"); it != j.end()) {
      if (!it->is_object()) return fail("\"dynamics\" must be an object");
      for (auto a = it->begin(); a != it->end(); ++a) {
        AxisDynamics d;
        if (!readDynamics(a.value(), d)) {
          return fail("dynamics of axis " + a.key() +
                      " must be {velocity, acceleration, jerk} finite numbers >= 0");
        }
        m.axisDynamics[a.key()] = d;
      }
    }
    if (auto it = j.find("tilt_deg"); it != j.end()) {
      if (!finiteNumber(*it) || std::abs(it->get<double>()) > 90) {
        return fail("\"tilt_deg\" must be a number within [-90, 90] degrees");
      }
      m.tiltDegrees = it->get<double>();
    }
    if (auto it = j.find("tip_offset"); it != j.end()) {
      double p[3];
      if (!readNumbers(*it, 3, p)) return fail("\"tip_offset\" must be 3 finite numbers");
      m.tipOffset = {p[0], p[1], p[2]};
    }
    if (auto it = j.find("step_angle_deg"); it != j.end()) {
      if (!finiteNumber(*it) || it->get<double>() < 0) {
        return fail("\"step_angle_deg\" must be a finite number >= 0");
      }
      m.stepAngleDegrees = it->get<double>();
    }
    if (auto it = j.find("safe_z"); it != j.end()) {
      if (!finiteNumber(*it)) return fail("\"safe_z\" must be a finite number");
      m.safeZ = it->get<double>();
    }
    if (auto it = j.find("axis_letters"); it != j.end()) {
      if (!it->is_object()) return fail("\"axis_letters\" must be an object {axis: letter}");
      for (auto a = it->begin(); a != it->end(); ++a) {
        if (!a.value().is_string()) return fail("axis_letters: the letter of axis " + a.key().substr(0, 20) + " must be a string");
        m.axisLetters[a.key()] = a.value().get<std::string>();
      }
      const Outcome ok = checkAxisLetters(m.kind, m.axisLetters);
      if (!ok.ok()) return fail(ok.message);
    }
    parseRobot(j);
    if (failed) return;
    if (auto it = j.find("nozzle"); it != j.end()) {
      if (!it->is_object()) return fail("\"nozzle\" must be an object");
      const std::pair<const char*, double*> keys[3] = {
          {"diameter", &m.nozzle.diameter},
          {"cone_half_angle_deg", &m.nozzle.coneHalfAngleDegrees},
          {"cone_length", &m.nozzle.coneLength}};
      for (const auto& k : keys) {
        auto v = it->find(k.first);
        if (v == it->end()) continue;
        if (!finiteNumber(*v) || v->get<double>() <= 0) {
          return fail("nozzle sizes must be positive finite numbers");
        }
        *k.second = v->get<double>();
      }
      if (m.nozzle.coneHalfAngleDegrees >= 90) {
        return fail("nozzle cone_half_angle_deg must be below 90");
      }
      if (auto c = it->find("carriage_size"); c != it->end()) {
        double s[3];
        if (!readNumbers(*c, 3, s) || !(s[0] > 0 && s[1] > 0 && s[2] > 0)) {
          return fail("nozzle carriage_size must be 3 positive finite numbers");
        }
        m.nozzle.carriageSize = {s[0], s[1], s[2]};
      }
    }
  }

  void parseRobot(const Json& j) {
    MachineProfile& m = r.machine;
    const bool robot = m.kind == MachineKind::Robot6;
    auto dh = j.find("dh");
    if (dh == j.end()) {
      if (robot) fail("a robot6 machine needs \"dh\" (6 rows [theta_offset, d, a, alpha])");
    } else {
      if (!dh->is_array() || dh->size() != 6) return fail("\"dh\" must have 6 rows");
      for (size_t i = 0; i < 6; ++i) {
        double row[4];
        if (!readNumbers((*dh)[i], 4, row)) {
          return fail("\"dh\" rows must be [theta_offset, d, a, alpha] finite numbers");
        }
        m.dh[i] = DhRow{row[0], row[1], row[2], row[3]};
      }
    }
    if (auto it = j.find("joint_limits"); it != j.end()) {
      if (!it->is_array() || it->size() != 6) return fail("\"joint_limits\" must have 6 pairs");
      for (size_t i = 0; i < 6; ++i) {
        double l[2];
        if (!readNumbers((*it)[i], 2, l)) {
          return fail("\"joint_limits\" entries must be [min, max] finite numbers");
        }
        if (l[0] > l[1]) return fail("joint limit " + std::to_string(i + 1) + " has min > max");
        m.jointLimits[i] = {l[0], l[1]};
      }
    }
    if (auto it = j.find("joint_dynamics"); it != j.end()) {
      if (!it->is_array() || it->size() != 6) return fail("\"joint_dynamics\" must have 6 entries");
      for (size_t i = 0; i < 6; ++i) {
        if (!readDynamics((*it)[i], m.jointDynamics[i])) {
          return fail("\"joint_dynamics\" entries must be {velocity, acceleration, jerk} >= 0");
        }
      }
    }
    if (auto it = j.find("joint_signs"); it != j.end()) {
      double signs[6];
      if (!readNumbers(*it, 6, signs)) return fail("\"joint_signs\" must be 6 numbers, each 1 or -1");
      for (int i = 0; i < 6; ++i) {
        if (signs[i] != 1 && signs[i] != -1) return fail("\"joint_signs\" must be 6 numbers, each 1 or -1");
        m.jointSigns[i] = signs[i] > 0 ? 1 : -1;
      }
    }
    if (auto it = j.find("ik_branches"); it != j.end()) {
      if (!it->is_number_integer() || it->get<int64_t>() < 1 || it->get<int64_t>() > 255) {
        return fail("\"ik_branches\" must be an integer 1..255 (bit b allows inverse-kinematics branch b)");
      }
      m.ikBranches = int(it->get<int64_t>());
    }
    if (auto it = j.find("flange_to_platform"); it != j.end()) {
      double t[16];
      if (!readNumbers(*it, 16, t)) return fail("\"flange_to_platform\" must be 16 finite numbers");
      Eigen::Matrix4d f;
      for (int i = 0; i < 16; ++i) f(i / 4, i % 4) = t[i];
      const Eigen::Matrix3d rot = f.topLeftCorner<3, 3>();
      const bool rigid = (rot.transpose() * rot - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <
                             1e-6 &&
                         rot.determinant() > 0 && f(3, 0) == 0 && f(3, 1) == 0 && f(3, 2) == 0 &&
                         f(3, 3) == 1;
      if (!rigid) return fail("\"flange_to_platform\" must be a rigid transform (rotation, translation)");
      m.flangeToPlatform = f;
    }
    if (auto it = j.find("nozzle_tip"); it != j.end()) {
      double p[3];
      if (!readNumbers(*it, 3, p)) return fail("\"nozzle_tip\" must be 3 finite numbers");
      m.nozzleTip = {p[0], p[1], p[2]};
    }
    if (auto it = j.find("nozzle_axis"); it != j.end()) {
      double p[3];
      if (!readNumbers(*it, 3, p)) return fail("\"nozzle_axis\" must be 3 finite numbers");
      const Eigen::Vector3d a(p[0], p[1], p[2]);
      const double n = a.norm();
      if (!(n > 1e-12) || !std::isfinite(n)) return fail("\"nozzle_axis\" must not be zero");
      // Unit axes are kept bit for bit (round trip); others are normalised.
      m.nozzleAxis = std::abs(n - 1) < 1e-15 ? a : Eigen::Vector3d(a / n);
    }
  }
};
}  // namespace

MachineParseResult machineFromJson(const std::string& text) {
  Parser p;
  try {
    const Json j = Json::parse(text, nullptr, false);
    if (j.is_discarded()) {
      p.fail("malformed JSON");
    } else {
      p.parse(j);
    }
  } catch (const std::exception& e) {  // never escapes the core (nlohmann type errors)
    p.fail(std::string("malformed machine: ") + e.what());
  }
  if (p.failed) p.r.machine = MachineProfile{};
  return p.r;
}

}  // namespace omnislice
