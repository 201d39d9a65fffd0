// SPDX-License-Identifier: MIT
#include "pipeline/auto_choice.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "common/math_constants.h"

namespace omnislice {

bool dominatedBy(const AutoBound& bound, double supportMm3, double timeS) {
  return bound.sound && (supportMm3 > bound.supportVolumeMm3 + bound.supportTieMm3 ||
                         (supportMm3 >= bound.supportVolumeMm3 - bound.supportTieMm3 && timeS >= bound.timeS));
}

double autoSupportTie(double extrusionMm, const Settings& settings) {
  // A few struts under a 40 mm part do not outweigh hours of print time.
  const double laid = extrusionMm * kPi / 4 * settings.filamentDiameter * settings.filamentDiameter;
  return std::max(1.0, 0.01 * laid);
}

namespace {

bool better(const AutoFigures& a, const AutoFigures& b, double supportTieMm3) {
  if (a.ok() != b.ok()) return a.ok();
  if (!a.ok()) return false;
  const VerifySection& va = *a.verify;
  const VerifySection& vb = *b.verify;
  if (va.sound != vb.sound) return va.sound;
  auto hardOk = [](const VerifySection& v) { return v.collisions == 0 && v.limits == 0 && !(v.leftOutMm > 0); };
  if (hardOk(va) != hardOk(vb)) return hardOk(va);
  const double sa = std::min(va.supported, va.minSupported), sb = std::min(vb.supported, vb.minSupported);
  if (std::abs(sa - sb) > 1e-9) return sa > sb;
  const double da = a.supportVolumeMm3 - b.supportVolumeMm3;
  if (std::abs(da) > supportTieMm3) return da < 0;
  return a.estimatedTimeS < b.estimatedTimeS;
}

// Why `chosen` was delivered over `other`, in a few words.
std::string whyNot(const AutoFigures& other, const AutoFigures& chosen, double supportTieMm3) {
  char text[200];
  if (!other.ok()) return other.method + " (" + other.message + ")";
  const VerifySection& v = *other.verify;
  if (!v.sound) return other.method + " (unsound: " + (v.failures.empty() ? std::string("see its check") : v.failures.front()) + ")";
  if (other.supportVolumeMm3 > chosen.supportVolumeMm3 + supportTieMm3) {
    std::snprintf(text, sizeof text, "%s (%.0f mm^3 of support)", other.method.c_str(), other.supportVolumeMm3);
  } else {
    std::snprintf(text, sizeof text, "%s (%.2f h)", other.method.c_str(), other.estimatedTimeS / 3600);
  }
  return text;
}

Status statusOfCode(const std::string& code) {
  for (Status s : {Status::EmptyInput, Status::UnsupportedFormat, Status::ParseError, Status::TruncatedFile,
                   Status::NonFiniteVertex, Status::DegenerateInput, Status::OpenMesh, Status::NonManifoldInput,
                   Status::SelfIntersecting, Status::InvalidOption, Status::IoError, Status::Cancelled,
                   Status::UnsoundProgram}) {
    if (code == statusCode(s)) return s;
  }
  return Status::Internal;  // also a worker lost in the page ("worker_failed")
}

}  // namespace

AutoDecision decideAuto(const std::vector<AutoFigures>& candidates, const Settings& settings) {
  AutoDecision d;
  for (size_t k = 0; k < candidates.size(); ++k) {
    const AutoFigures& f = candidates[k];
    if (f.status == "cancelled") {
      d.status = Status::Cancelled;
      d.message = "cancelled";
      return d;
    }
    // As one after another would: an unsound program that could still win is made again with
    // the remedies (its first program is the same, so the same candidates get them).
    if (!f.full && f.ok() && !f.verify->sound && settings.verifyAttempts > 1 &&
        !(d.bound && dominatedBy(*d.bound, f.supportVolumeMm3, f.estimatedTimeS))) {
      d.rerun = int(k);
      return d;
    }
    AutoCandidate c;
    c.method = f.method;
    c.status = f.status;
    c.message = f.message;
    c.stoppedEarly = f.status == "dominated";
    c.supportVolumeMm3 = f.supportVolumeMm3;
    c.estimatedTimeS = f.estimatedTimeS;
    c.totalMs = f.ms;
    if (f.ok()) {
      VerifySection v = *f.verify;
      v.attempts = {};
      c.verify = std::move(v);
    }
    d.section.candidates.push_back(c);
    if (!f.ok()) continue;
    const double tie = d.chosen >= 0 ? std::min(autoSupportTie(f.extrusionMm, settings),
                                                autoSupportTie(candidates[d.chosen].extrusionMm, settings))
                                     : 1.0;
    if (d.chosen < 0 || better(f, candidates[d.chosen], tie)) {
      d.chosen = int(k);
      d.bound = AutoBound{f.verify->sound, f.supportVolumeMm3, f.estimatedTimeS, f.method,
                          autoSupportTie(f.extrusionMm, settings)};
    }
  }
  if (d.chosen < 0) {
    // The first failure stands for all when nothing prints.
    d.status = candidates.empty() ? Status::InvalidOption : statusOfCode(candidates.front().status);
    std::string why;
    for (const AutoCandidate& c : d.section.candidates) why += (why.empty() ? "" : "; ") + c.method + ": " + c.message;
    d.message = candidates.empty() ? "no method prints on this machine" : "no method made a program: " + why;
    return d;
  }
  const AutoFigures& best = candidates[size_t(d.chosen)];
  d.section.chosen = best.method;
  const VerifySection& v = *best.verify;
  char head[300];
  std::snprintf(head, sizeof head, "%s: %s, supported %.3f, %.0f mm^3 of support, %.2f h", best.method.c_str(),
                v.sound ? "sound" : "the best of unsound programs", v.supported, best.supportVolumeMm3,
                best.estimatedTimeS / 3600);
  d.section.reason = head;
  std::string others;
  for (const AutoFigures& c : candidates) {
    if (c.method == best.method) continue;
    others += (others.empty() ? "" : ", ") + whyNot(c, best, autoSupportTie(best.extrusionMm, settings));
  }
  if (!others.empty()) d.section.reason += "; over " + others;
  if (settings.verify == VerifyMode::Refuse && !v.sound) {
    d.status = Status::UnsoundProgram;
    d.message = v.statement;
  }
  return d;
}

std::string autoPlanJson(const std::vector<std::pair<std::string, Settings>>& candidates, const Settings& settings) {
  using Json = nlohmann::ordered_json;
  Json list = Json::array();
  for (const auto& [method, s] : candidates) {
    list.push_back({{"method", method},
                    {"settings",
                     {{"method", method},
                      {"verify", findSetting("verify")->format(s)},
                      {"verify_attempts", findSetting("verify_attempts")->format(s)}}}});
  }
  const Json j = {{"candidates", list},
                  {"rerun_settings", {{"verify_attempts", findSetting("verify_attempts")->format(settings)}}}};
  return j.dump();
}

std::string autoDecisionJson(const AutoDecision& d) {
  nlohmann::ordered_json j;
  if (d.rerun >= 0) {
    j["rerun"] = d.rerun;
    return j.dump();
  }
  j["chosen"] = d.chosen;
  j["status"] = statusCode(d.status);
  j["message"] = d.message;
  j["auto"] = nlohmann::ordered_json::parse(autoSectionJson(d.section));
  return j.dump();
}

AutoFigures autoFiguresFromJson(const std::string& candidateJson, std::string* error) {
  AutoFigures f;
  try {
    const nlohmann::json j = nlohmann::json::parse(candidateJson);
    f.method = j.at("method").get<std::string>();
    f.status = j.value("status", std::string("ok"));
    f.message = j.value("message", std::string());
    f.full = j.value("full", false);
    f.ms = j.value("ms", 0.0);
    const nlohmann::json& r = j.contains("report") ? j.at("report") : nlohmann::json();
    if (r.is_object()) {
      f.supportVolumeMm3 = r.value("support_volume_mm3", 0.0);
      f.estimatedTimeS = r.value("estimated_time_s", 0.0);
      f.extrusionMm = r.value("extrusion_mm", 0.0);
      if (r.contains("verify") && r.at("verify").is_object()) {
        const nlohmann::json& v = r.at("verify");
        VerifySection s;
        s.mode = v.value("mode", std::string());
        s.sound = v.at("sound").get<bool>();
        s.inside = v.value("inside", 0.0);
        s.coverage = v.value("coverage", 0.0);
        s.supported = v.value("supported", 0.0);
        s.collisions = v.value("collisions", size_t(0));
        s.limits = v.value("limits", size_t(0));
        s.leftOutMm = v.value("left_out_mm", 0.0);
        if (v.contains("criteria")) s.minSupported = v.at("criteria").value("supported", 0.0);
        s.failures = v.value("failures", std::vector<std::string>());
        s.statement = v.value("statement", std::string());
        f.verify = s;
      }
    }
    if (f.ok() && !f.verify) {
      if (error) *error = f.method + ": a candidate's report has no verify section";
      f.status = "internal";
    }
  } catch (const std::exception& e) {
    if (error) *error = std::string("a candidate is not valid JSON: ") + e.what();
    f.status = "internal";
  }
  return f;
}

}  // namespace omnislice
