// SPDX-License-Identifier: MIT
// The one pipeline every front end calls (CLI, wasm API, worker, page): mesh bytes -> read ->
// validate/repair -> place -> method (method.h) -> motion -> program -> report, plus info and
// verify.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "common/progress.h"
#include "common/status.h"
#include "mesh/mesh.h"
#include "pipeline/preview.h"
#include "pipeline/report.h"
#include "pipeline/settings.h"

namespace omnislice {

struct SliceOutput : Outcome {
  std::string program;                     // program text (G-code, robot CSV or URScript)
  std::string programExtension = "gcode";  // "gcode" | "csv" | "script"
  SliceReport report;                      // what was measured, typed
  std::string reportJson;                  // the same as JSON (sliceReportJson)
  std::string infoJson;                    // the input's info (inputReportJson)
  SlicePreview preview;                    // what viewers draw
  Mesh partMesh;                           // the printed solid (part frame), for viewers
  int layers = 0;                          // layers that deposit material (program markers)
  std::vector<Warning> warnings;           // also the report's "warnings" ([{code, message}])
};

// Slice mesh bytes with settings. Every failure is a Status with a message (never throws).
SliceOutput runSlice(const uint8_t* data, size_t size, const std::string& fileName,
                     const Settings& settings, const ProgressFn& progress = {});

// method = auto in a pool of workers (the page, workers/auto-pool.js): the same choice as runSlice
// makes in threads, with each candidate sliced on its own. planAuto: the candidates for this input
// and machine, {"candidates": [{"method", "settings": {key: value}}], "rerun_settings": {...}}:
// slice each with the user's settings changed by its `settings`. chooseAuto: given each
// candidate's {"method", "status" ("ok" or the error code), "message", "ms", "full" (made with
// rerun_settings), "report" (its report JSON, or null)}, in the plan's order, either {"rerun": k}
// (slice candidate k again with rerun_settings, set its full, and ask again) or {"chosen": k
// (-1: none made a program), "status", "message", "auto": the report's auto section}.
std::string planAuto(const uint8_t* data, size_t size, const std::string& fileName, const Settings& settings,
                     Outcome* outcome);
std::string chooseAuto(const Settings& settings, const std::vector<std::string>& candidatesJson, Outcome* outcome);

struct InfoOutput : Outcome {
  std::string infoJson;      // `omnislice info` JSON
  Mesh partMesh;             // placed mesh
};

// Read, validate (repairing as the settings' `repair` and method would: repair = auto with a
// method that slices a solid closes a mesh that does not bound one) and place by
// settings.placement; status is an error only when the file cannot be read at all.
InfoOutput runInfo(const uint8_t* data, size_t size, const std::string& fileName,
                   const Settings& settings, const ProgressFn& progress = {});

struct VerifyOutput : Outcome {
  std::string verifyJson;    // verifyReportJson()
};

// Verify a program against the mesh it was made from (the header's placement is applied to the
// mesh bytes), within a memory budget of memoryMb (setting memory_mb's meaning).
VerifyOutput runVerify(const std::string& programText, const uint8_t* meshData, size_t meshSize,
                       const std::string& meshName, const ProgressFn& progress = {},
                       double memoryMb = kDefaultMemoryBudgetMb);

}  // namespace omnislice
