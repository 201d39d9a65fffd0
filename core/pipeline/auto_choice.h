// SPDX-License-Identifier: MIT
// method = auto's choice among candidates, on their figures alone: the same rule whether the
// candidates ran one after another, in threads (pipeline.cpp runAuto) or in a pool of workers
// (the page: pipeline.h chooseAuto over their reports' JSON).
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "common/status.h"
#include "pipeline/report.h"
#include "pipeline/settings.h"

namespace omnislice {

// One candidate as the choice sees it.
struct AutoFigures {
  std::string method;
  std::string status = "ok";  // "ok", "dominated", or the error code that stopped it
  std::string message;
  bool full = false;          // made with every attempt the settings allow (verify_attempts)
  double ms = 0;              // its wall time
  std::optional<VerifySection> verify;
  double supportVolumeMm3 = 0, estimatedTimeS = 0, extrusionMm = 0;
  bool ok() const { return status == "ok"; }
};

// The best candidate so far, as far as a later one's check could not change the order.
struct AutoBound {
  bool sound = false;
  double supportVolumeMm3 = 0;
  double timeS = 0;
  std::string method;
  double supportTieMm3 = 1;  // autoSupportTie() of it
};

// A program with this support and time cannot beat the bound's, whatever its check finds.
bool dominatedBy(const AutoBound& bound, double supportMm3, double timeS);

// Support volumes closer than this tie in the ranking: 1 % of the material the program lays, at
// least 1 mm^3.
double autoSupportTie(double extrusionMm, const Settings& settings);

struct AutoDecision {
  // >= 0: this candidate is unsound, made with one attempt, and could still win: make it again
  // with every attempt (its `full` set) and decide again. Otherwise the choice below.
  int rerun = -1;
  int chosen = -1;                  // the delivered candidate; -1 when none made a program
  std::optional<AutoBound> bound;   // the chosen one's bound
  AutoSection section;              // the report's `auto` section (with chosen and reason)
  Status status = Status::Ok;       // not Ok when none made a program (the first failure's code)
  std::string message;
};

// The choice, in the candidates' order: a program beats none; a sound one an unsound one; then
// one without collisions, left-out path or limit violations; then the higher supported share up
// to the soundness bound; then less support (ties within autoSupportTie); then less time.
AutoDecision decideAuto(const std::vector<AutoFigures>& candidates, const Settings& settings);

// The page's plan (pipeline.h planAuto): {"candidates": [{method, settings: {key: value}}],
// "rerun_settings": {key: value}}, the settings being those that differ from the user's.
std::string autoPlanJson(const std::vector<std::pair<std::string, Settings>>& candidates, const Settings& settings);

// A decision as JSON (pipeline.h chooseAuto).
std::string autoDecisionJson(const AutoDecision& d);

// A candidate's figures from its slice report's JSON (sliceReportJson; null for a failure).
AutoFigures autoFiguresFromJson(const std::string& candidateJson, std::string* error);

}  // namespace omnislice
