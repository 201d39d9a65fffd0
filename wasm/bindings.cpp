// SPDX-License-Identifier: MIT
// Embind declarations only: the raw `_`-prefixed facade over core/pipeline. Marshalling lives in
// helpers.cpp; defaults, validation and typed errors in the JS wrapper omnislice.js.
#include <emscripten/bind.h>

#include "helpers.h"

EMSCRIPTEN_BINDINGS(omnislice) {
  using namespace omnislice::wasm;
  emscripten::function("_slice", &sliceJs);
  emscripten::function("_info", &infoJs);
  emscripten::function("_autoPlan", &autoPlanJs);
  emscripten::function("_autoChoose", &autoChooseJs);
  emscripten::function("_verify", &verifyJs);
  emscripten::function("_parseMachine", &parseMachineJs);
  emscripten::function("_machines", &machinesJs);
  emscripten::function("_replay", &replayJs);
  emscripten::function("_defaultSettings", &defaultSettingsJs);
  emscripten::function("_settingsSchema", &settingsSchemaJs);
  emscripten::function("_heapStats", &heapStatsJs);
  emscripten::function("_abortForTest", &abortForTest);
  emscripten::function("_allocateForTest", &allocateForTest);
}
