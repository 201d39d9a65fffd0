// SPDX-License-Identifier: MIT
// Marshalling between JS values and the pipeline (core/pipeline/pipeline.h). Each function takes
// typed arrays / strings, calls one pipeline function and returns a plain JS object whose arrays
// are heap COPIES (never views: memory growth would invalidate them). No geometry logic here.
#pragma once
#include <emscripten/val.h>

#include <string>

namespace omnislice::wasm {

// Slice mesh bytes. bytes: Uint8Array (or ArrayBuffer) of the file; name: file name (extension
// picks the format); settingsLines: "key=value" lines applied with setSetting(); progress: JS
// function(stage, fraction, search) or undefined (returning false cancels); search is undefined
// or, when a search level is done, {line, level, J_G, beams} (common/progress.h
// SearchLevelProgress).
// Returns {status, message, program: Uint8Array, report, info (JSON strings), layers,
// preview: {positions: Float32Array, features: Uint8Array, layers: Uint32Array,
// machine: Float32Array (6 machine values per segment end)}, programExtension ("gcode" | "csv" |
// "script"), mesh: {positions: Float32Array, indices: Uint32Array}}.
emscripten::val sliceJs(const emscripten::val& bytes, const std::string& name,
                        const std::string& settingsLines, const emscripten::val& progress);

// method = auto in a pool of workers (pipeline.h planAuto): {status, message, plan (JSON string)}.
emscripten::val autoPlanJs(const emscripten::val& bytes, const std::string& name, const std::string& settingsLines);

// method = auto's choice (pipeline.h chooseAuto) over candidates' JSON strings (an Array):
// {status, message, decision (JSON string)}.
emscripten::val autoChooseJs(const std::string& settingsLines, const emscripten::val& candidates);

// Read, validate and place. placementLines: "key=value" lines (placement keys of setSetting).
// Returns {status, message, info (JSON string), mesh: {positions, indices}}.
emscripten::val infoJs(const emscripten::val& bytes, const std::string& name,
                       const std::string& placementLines, const emscripten::val& progress);

// Verify a program (G-code text) against the mesh bytes it was made from, within a memory budget
// of memoryMb. Returns {status, message, verify (JSON string)}.
emscripten::val verifyJs(const std::string& program, const emscripten::val& meshBytes,
                         const std::string& meshName, const emscripten::val& progress, double memoryMb);

// Parse a machine profile JSON (machineFromJson) and write it back in the program header's form
// (machineJson). Returns {status, message, json (one line, when ok)}.
emscripten::val parseMachineJs(const std::string& json);

// Replay a program of any kind (readProgram): its machine and its moves as preview buffers for the
// machine animation, one segment per replayed piece that moves the tip. Returns {status, message,
// machine (machineJson), format ("gcode" | "csv" | "urscript" | "rapid" | "krl"), layers, preview: {positions,
// features, layers, machine}}.
emscripten::val replayJs(const std::string& program);

// Built-in machine profiles (builtinMachineNames(), builtinMachine() sized by the settings'
// bed_size and nozzle). settingsLines: "key=value" lines. Returns {status, message,
// machines: [{name, json (machineJson, one line)}...]} in display order.
emscripten::val machinesJs(const std::string& settingsLines);

// Default settings: {values: {key: valueText}, keys: [key...] in listSettings() order}.
emscripten::val defaultSettingsJs();

// The settings table (settingsSchemaJson): JSON text of [{key, type, default, min, max, unit,
// help, choices, method}, ...] in listing order.
std::string settingsSchemaJs();

// The instance's memory: {heapBytes: the wasm linear memory (it only grows), usedBytes: bytes
// malloc has handed out and not taken back (mallinfo's uordblks), blocks: mallinfo's ordblks
// (free chunks)}. The soak (scripts/soak.mjs) watches usedBytes across jobs for leaks.
emscripten::val heapStatsJs();

// Test hook for the worker's crash path: aborts the wasm instance (std::abort).
void abortForTest();

// Test hook for an allocation that fails: allocates `megabytes` MB (and frees them) under the same
// guard as every call; beyond the 4 GB heap it is the out_of_memory status, and the instance
// stays usable.
emscripten::val allocateForTest(double megabytes);

}  // namespace omnislice::wasm
