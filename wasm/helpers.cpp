// SPDX-License-Identifier: MIT
#include "helpers.h"

#include <emscripten/heap.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <malloc.h>
#include <new>
#include <vector>

#include "common/memory_budget.h"
#include "common/status.h"
#include "pipeline/pipeline.h"
#include "pipeline/settings.h"
#include "machine/machine.h"
#include "machine/machine_json.h"
#include "program/read_program.h"
#include "toolpath/toolpath.h"

namespace omnislice::wasm {
namespace {

using emscripten::val;

// One memcpy from a JS Uint8Array/ArrayBuffer into the wasm heap.
std::vector<uint8_t> bytesFromJs(const val& bytes) {
  val view = bytes;
  if (bytes.instanceof(val::global("ArrayBuffer"))) view = val::global("Uint8Array").new_(bytes);
  if (view.isUndefined() || view.isNull() || !view.instanceof(val::global("Uint8Array"))) return {};
  return emscripten::convertJSArrayToNumberVector<uint8_t>(view);
}

// new Ctor(view) copies the elements out of the heap, so growth cannot invalidate the result.
template <class T>
val copyArray(const char* ctor, const T* data, size_t count) {
  if (count == 0) return val::global(ctor).new_(0);
  return val::global(ctor).new_(val(emscripten::typed_memory_view(count, data)));
}

val meshToJs(const Mesh& mesh) {
  std::vector<float> positions(mesh.positions.begin(), mesh.positions.end());
  val out = val::object();
  out.set("positions", copyArray("Float32Array", positions.data(), positions.size()));
  out.set("indices", copyArray("Uint32Array", mesh.triangles.data(), mesh.triangles.size()));
  return out;
}

val statusObject(Status status, const std::string& message) {
  val out = val::object();
  out.set("status", std::string(statusCode(status)));
  out.set("message", message);
  return out;
}

// A progress callback calling the JS function with (stage, fraction) or, when a search level is
// done, (stage, fraction, {line, level, J_G, beams}); false from JS cancels, anything else
// continues.
ProgressFn progressFromJs(const val& fn) {
  if (fn.typeOf().as<std::string>() != "function") return {};
  return [fn](const ProgressEvent& e) {
    if (!e.search) return !fn(std::string(e.stage), e.fraction).isFalse();
    val search = val::object();
    search.set("line", std::string(e.search->line));
    search.set("level", e.search->level);
    search.set("J_G", e.search->jgMm2);
    search.set("beams", e.search->beams);
    return !fn(std::string(e.stage), e.fraction, search).isFalse();
  };
}

// Apply "key=value" lines with setSetting. Blank lines are skipped.
Outcome applySettingLines(Settings& settings, const std::string& lines) {
  size_t start = 0;
  while (start < lines.size()) {
    size_t end = lines.find('\n', start);
    if (end == std::string::npos) end = lines.size();
    std::string line = lines.substr(start, end - start);
    start = end + 1;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    size_t eq = line.find('=');
    if (eq == std::string::npos) {
      return {Status::InvalidOption, "setting line without '=': \"" + line + "\""};
    }
    Outcome o = setSetting(settings, line.substr(0, eq), line.substr(eq + 1));
    if (!o.ok()) return o;
  }
  return {};
}

// Runs body; a C++ exception (e.g. bad_alloc on a huge mesh) becomes an `internal` status object.
template <class F>
val guarded(F&& body) {
  try {
    return body();
  } catch (const std::bad_alloc&) {
    const Outcome o = allocationFailed("running (the wasm heap ends at 4 GB)");
    return statusObject(o.status, o.message);
  } catch (const std::exception& e) {
    return statusObject(Status::Internal, std::string("unexpected exception: ") + e.what());
  }
}

template <class T>
void setArray(val& obj, const char* name, const char* ctor, const std::vector<T>& v) {
  obj.set(name, copyArray(ctor, v.data(), v.size()));
}

// The preview as one flat object of typed arrays (the page's names): the tool path, then each
// method's section under the names viewers know.
val previewToJs(const SlicePreview& p) {
  val out = val::object();
  const ToolpathPreview& t = p.toolpath;
  setArray(out, "positions", "Float32Array", t.positions);
  setArray(out, "features", "Uint8Array", t.features);
  setArray(out, "layers", "Uint32Array", t.layers);
  setArray(out, "machine", "Float32Array", t.machine);
  setArray(out, "axes", "Float32Array", t.axes);
  setArray(out, "poses", "Float32Array", t.poses);
  setArray(out, "curves", "Uint32Array", t.curves);
  const LayerSurfacePreview& s = p.method.surfaces;
  setArray(out, "surfacePositions", "Float32Array", s.positions);
  setArray(out, "surfaceTriangles", "Uint32Array", s.triangles);
  setArray(out, "surfaceLayers", "Uint32Array", s.layers);
  const VoxelPreview& v = p.method.voxel;
  setArray(out, "missedVoxels", "Float32Array", v.missed);
  setArray(out, "supportVoxels", "Float32Array", v.support);
  out.set("voxelWidth", v.width);
  const GeodesicPreview& g = p.method.geodesic;
  setArray(out, "fieldPositions", "Float32Array", g.fieldPositions);
  setArray(out, "fieldTriangles", "Uint32Array", g.fieldTriangles);
  setArray(out, "fieldValues", "Float32Array", g.fieldValues);
  setArray(out, "nodePositions", "Float32Array", g.nodePositions);
  setArray(out, "nodeLayers", "Uint32Array", g.nodeLayers);
  setArray(out, "treeEdges", "Uint32Array", g.treeEdges);
  setArray(out, "sequence", "Uint32Array", g.sequence);
  setArray(out, "skippedSegments", "Float32Array", g.skippedSegments);
  setArray(out, "skippedLayers", "Uint32Array", g.skippedLayers);
  const MultidirPreview& m = p.method.multidir;
  setArray(out, "partPositions", "Float32Array", m.partPositions);
  setArray(out, "partTriangles", "Uint32Array", m.partTriangles);
  setArray(out, "partIds", "Uint32Array", m.partIds);
  setArray(out, "riskyBefore", "Uint8Array", m.riskyBefore);
  setArray(out, "riskyAfter", "Uint8Array", m.riskyAfter);
  setArray(out, "unsupportedPoints", "Float32Array", p.verify.unsupported);
  setArray(out, "collisionPoints", "Float32Array", p.verify.collisions);
  return out;
}

}  // namespace

val sliceJs(const val& bytes, const std::string& name, const std::string& settingsLines,
            const val& progress) {
  return guarded([&] {
    Settings settings;
    Outcome applied = applySettingLines(settings, settingsLines);
    if (!applied.ok()) return statusObject(applied.status, applied.message);
    std::vector<uint8_t> data = bytesFromJs(bytes);
    SliceOutput r = runSlice(data.data(), data.size(), name, settings, progressFromJs(progress));
    val out = statusObject(r.status, r.message);
    out.set("program", copyArray("Uint8Array", reinterpret_cast<const uint8_t*>(r.program.data()),
                                 r.program.size()));
    out.set("report", r.reportJson);
    out.set("info", r.infoJson);
    out.set("layers", r.layers);
    out.set("preview", previewToJs(r.preview));
    out.set("programExtension", r.programExtension);
    out.set("mesh", meshToJs(r.partMesh));
    return out;
  });
}

val autoPlanJs(const val& bytes, const std::string& name, const std::string& settingsLines) {
  return guarded([&] {
    Settings settings;
    Outcome applied = applySettingLines(settings, settingsLines);
    if (!applied.ok()) return statusObject(applied.status, applied.message);
    std::vector<uint8_t> data = bytesFromJs(bytes);
    Outcome o;
    const std::string plan = planAuto(data.data(), data.size(), name, settings, &o);
    val out = statusObject(o.status, o.message);
    out.set("plan", plan);
    return out;
  });
}

val autoChooseJs(const std::string& settingsLines, const val& candidates) {
  return guarded([&] {
    Settings settings;
    Outcome applied = applySettingLines(settings, settingsLines);
    if (!applied.ok()) return statusObject(applied.status, applied.message);
    const std::vector<std::string> list = emscripten::vecFromJSArray<std::string>(candidates);
    Outcome o;
    const std::string decision = chooseAuto(settings, list, &o);
    val out = statusObject(o.status, o.message);
    out.set("decision", decision);
    return out;
  });
}

val infoJs(const val& bytes, const std::string& name, const std::string& placementLines,
           const val& progress) {
  return guarded([&] {
    Settings settings;
    Outcome applied = applySettingLines(settings, placementLines);
    if (!applied.ok()) return statusObject(applied.status, applied.message);
    std::vector<uint8_t> data = bytesFromJs(bytes);
    InfoOutput r = runInfo(data.data(), data.size(), name, settings,
                           progressFromJs(progress));
    val out = statusObject(r.status, r.message);
    out.set("info", r.infoJson);
    out.set("mesh", meshToJs(r.partMesh));
    return out;
  });
}

val verifyJs(const std::string& program, const val& meshBytes, const std::string& meshName,
             const val& progress, double memoryMb) {
  return guarded([&] {
    std::vector<uint8_t> data = bytesFromJs(meshBytes);
    VerifyOutput r = runVerify(program, data.data(), data.size(), meshName,
                               progressFromJs(progress), memoryMb);
    val out = statusObject(r.status, r.message);
    out.set("verify", r.verifyJson);
    return out;
  });
}

val parseMachineJs(const std::string& json) {
  return guarded([&] {
    MachineParseResult r = machineFromJson(json);
    val out = statusObject(r.status, r.message);
    if (r.ok()) out.set("json", machineJson(r.machine));
    return out;
  });
}

val replayJs(const std::string& program) {
  return guarded([&] {
    ParsedProgram p = readProgram(program);
    val out = statusObject(p.status, p.message);
    if (!p.ok()) return out;
    out.set("machine", machineJson(p.machine));
    out.set("format", p.format);
    out.set("layers", p.layerCount);
    const ToolpathPreview t = programPreview(p);
    val preview = val::object();
    setArray(preview, "positions", "Float32Array", t.positions);
    setArray(preview, "features", "Uint8Array", t.features);
    setArray(preview, "layers", "Uint32Array", t.layers);
    setArray(preview, "machine", "Float32Array", t.machine);
    setArray(preview, "poses", "Float32Array", t.poses);
    out.set("preview", preview);
    return out;
  });
}

val machinesJs(const std::string& settingsLines) {
  return guarded([&] {
    Settings settings;
    Outcome applied = applySettingLines(settings, settingsLines);
    if (!applied.ok()) return statusObject(applied.status, applied.message);
    val list = val::array();
    for (const std::string& name : builtinMachineNames()) {
      MachineProfileResult r = builtinMachine(name, settings.bedSize, settings.nozzleDiameter);
      if (!r.ok()) return statusObject(r.status, r.message);
      val item = val::object();
      item.set("name", name);
      item.set("json", machineJson(r.machine));
      list.call<void>("push", item);
    }
    val out = statusObject(Status::Ok, "");
    out.set("machines", list);
    return out;
  });
}

std::string settingsSchemaJs() { return settingsSchemaJson(); }

val defaultSettingsJs() {
  val out = val::object();
  val keys = val::array();
  for (const auto& [key, value] : listSettings(Settings{})) {
    out.set(key, value);
    keys.call<void>("push", key);
  }
  val result = val::object();
  result.set("values", out);
  result.set("keys", keys);
  return result;
}

emscripten::val heapStatsJs() {
  const struct mallinfo mi = mallinfo();
  emscripten::val out = emscripten::val::object();
  out.set("heapBytes", static_cast<double>(emscripten_get_heap_size()));
  out.set("usedBytes", static_cast<double>(mi.uordblks));
  out.set("blocks", static_cast<double>(mi.ordblks));
  return out;
}

void abortForTest() { std::abort(); }

val allocateForTest(double megabytes) {
  return guarded([&] {
    const double bytes = std::min(std::max(0.0, megabytes) * 1024 * 1024, double(SIZE_MAX));
    // operator new throws std::bad_alloc when malloc cannot grow the heap (as every container does).
    void* block = ::operator new(static_cast<size_t>(bytes));
    static_cast<volatile uint8_t*>(block)[0] = 1;
    ::operator delete(block);
    return statusObject(Status::Ok, "");
  });
}

}  // namespace omnislice::wasm
