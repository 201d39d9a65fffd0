// SPDX-License-Identifier: MIT
#include "program/machine.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "program/machine_json.h"

namespace omnislice {

MachineProfile cartesian3Profile(const Eigen::Vector3d& bedSize, double nozzleDiameter) {
  MachineProfile m;
  m.kind = "cartesian3";
  m.axisLimits["X"] = {-0.5 * bedSize.x(), 0.5 * bedSize.x()};
  m.axisLimits["Y"] = {-0.5 * bedSize.y(), 0.5 * bedSize.y()};
  m.axisLimits["Z"] = {0.0, bedSize.z()};
  m.nozzle.diameter = nozzleDiameter;
  return m;
}

std::vector<std::string> machineAxisLetters(const std::string& kind) {
  if (kind == "cartesian3") return {"X", "Y", "Z"};
  if (kind == "rotary4") return {"X", "Y", "Z", "A"};
  if (kind == "table5") return {"X", "Y", "Z", "B", "C"};
  return {};
}

std::string machineJson(const MachineProfile& machine) {
  // ordered_json keeps the key order of the format page (kind first).
  nlohmann::ordered_json j;
  j["kind"] = machine.kind;
  if (machine.kind != "cartesian3") {
    j["pivot"] = {machine.pivot.x(), machine.pivot.y(), machine.pivot.z()};
  }
  nlohmann::ordered_json limits = nlohmann::ordered_json::object();
  // Axis letters of the kind first in their natural order, then any others alphabetically.
  std::vector<std::string> order = machineAxisLetters(machine.kind);
  for (const auto& kv : machine.axisLimits) {
    if (std::find(order.begin(), order.end(), kv.first) == order.end()) order.push_back(kv.first);
  }
  for (const std::string& axis : order) {
    auto it = machine.axisLimits.find(axis);
    if (it != machine.axisLimits.end()) limits[axis] = {it->second.first, it->second.second};
  }
  j["axis_limits"] = limits;
  j["nozzle"] = {{"diameter", machine.nozzle.diameter},
                 {"cone_half_angle_deg", machine.nozzle.coneHalfAngleDegrees},
                 {"cone_length", machine.nozzle.coneLength}};
  return j.dump();
}

namespace {
bool finiteNumber(const nlohmann::json& v) { return v.is_number() && std::isfinite(v.get<double>()); }
}  // namespace

MachineParseResult machineFromJson(const std::string& text) {
  MachineParseResult r;
  nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  auto fail = [&](const std::string& msg) {
    r.status = Status::ParseError;
    r.message = "machine JSON: " + msg;
    return r;
  };
  if (j.is_discarded() || !j.is_object()) return fail("not a JSON object");
  if (!j.contains("kind") || !j["kind"].is_string()) return fail("missing \"kind\"");
  r.machine.kind = j["kind"].get<std::string>();
  if (j.contains("pivot")) {
    const auto& p = j["pivot"];
    if (!p.is_array() || p.size() != 3 || !finiteNumber(p[0]) || !finiteNumber(p[1]) ||
        !finiteNumber(p[2])) {
      return fail("\"pivot\" must be 3 finite numbers");
    }
    r.machine.pivot = {p[0].get<double>(), p[1].get<double>(), p[2].get<double>()};
  }
  if (j.contains("axis_limits")) {
    const auto& l = j["axis_limits"];
    if (!l.is_object()) return fail("\"axis_limits\" must be an object");
    for (auto it = l.begin(); it != l.end(); ++it) {
      const auto& v = it.value();
      if (!v.is_array() || v.size() != 2 || !finiteNumber(v[0]) || !finiteNumber(v[1])) {
        return fail("limit of axis " + it.key() + " must be [min, max] finite numbers");
      }
      const double lo = v[0].get<double>(), hi = v[1].get<double>();
      if (lo > hi) return fail("limit of axis " + it.key() + " has min > max");
      r.machine.axisLimits[it.key()] = {lo, hi};
    }
  }
  if (j.contains("nozzle")) {
    const auto& n = j["nozzle"];
    if (!n.is_object()) return fail("\"nozzle\" must be an object");
    auto read = [&](const char* key, double& out) {
      if (!n.contains(key)) return true;
      if (!finiteNumber(n[key]) || n[key].get<double>() <= 0) return false;
      out = n[key].get<double>();
      return true;
    };
    if (!read("diameter", r.machine.nozzle.diameter) ||
        !read("cone_half_angle_deg", r.machine.nozzle.coneHalfAngleDegrees) ||
        !read("cone_length", r.machine.nozzle.coneLength)) {
      return fail("nozzle sizes must be positive finite numbers");
    }
  }
  return r;
}

}  // namespace omnislice
