// SPDX-License-Identifier: MIT
#include "fuzz_checks.h"

#include <cmath>
#include <cstring>
#include <string>
#include <utility>

#include "machine/machine_json.h"
#include "mesh/inflate.h"
#include "mesh/read_mesh.h"
#include "pipeline/settings.h"
#include "program/read_program.h"
#include "tet/tet_mesh.h"

namespace omnislice::fuzz {

namespace {

// A failed status must say why; an ok one must not carry an error message.
std::string statusProblem(const Outcome& r) {
  if (!r.ok() && r.message.empty()) return std::string("status ") + statusCode(r.status) + " without a message";
  return "";
}

// A read mesh: whole triangles, every index names a vertex; the same bytes read again give the
// same mesh (no state carried between reads).
std::string meshProblem(const ReadMeshResult& r, const ReadMeshResult& again) {
  if (std::string s = statusProblem(r); !s.empty()) return s;
  if (r.status != again.status || r.message != again.message) return "a second read gave another status";
  if (!r.ok()) return "";
  const Mesh& m = r.mesh;
  if (m.positions.size() % 3 != 0) return "positions are not whole vertices";
  if (m.triangles.size() % 3 != 0) return "triangles are not whole";
  if (m.triangles.empty()) return "ok without a face";
  const size_t n = m.positions.size() / 3;
  for (uint32_t i : m.triangles) {
    if (i >= n) return "a triangle index names no vertex";
  }
  if (m.triangles != again.mesh.triangles) return "a second read gave other triangles";
  for (size_t i = 0; i < m.positions.size(); ++i) {
    const double a = m.positions[i], b = again.mesh.positions[i];
    if (!(a == b || (std::isnan(a) && std::isnan(b)))) return "a second read gave other positions";
  }
  return "";
}

// Through readMesh, the entry every caller uses, with the format's extension as the name (3MF:
// the zip, its directory, inflate, the model XML).
template <const char* Name>
std::string checkReader(const uint8_t* data, size_t size) {
  return meshProblem(readMesh(data, size, Name), readMesh(data, size, Name));
}
constexpr char kStl[] = "fuzz.stl", kObj[] = "fuzz.obj", kOff[] = "fuzz.off", kPly[] = "fuzz.ply",
               k3mf[] = "fuzz.3mf";

std::string checkInflate(const uint8_t* data, size_t size) {
  constexpr size_t kMax = 1 << 20;
  const InflateResult r = inflateRaw(data, size, kMax);
  if (std::string s = statusProblem(r); !s.empty()) return s;
  if (!r.ok()) return r.data.empty() ? "" : "a failed inflate returned bytes";
  if (r.data.size() > kMax) return "inflate wrote past its limit";
  if (r.consumed > size) return "inflate consumed more bytes than it was given";
  // The stream re-read from its consumed prefix gives the same bytes.
  const InflateResult again = inflateRaw(data, r.consumed, kMax);
  if (!again.ok() || again.data != r.data) return "the consumed prefix inflates to other bytes";
  return "";
}

std::string checkTet(const uint8_t* data, size_t size) {
  const TetMeshResult r = readTetMesh(data, size);
  if (std::string s = statusProblem(r); !s.empty()) return s;
  if (!r.ok()) return "";
  const TetMesh& m = r.mesh;
  if (m.positions.size() % 3 != 0 || m.tets.size() % 4 != 0 || m.tets.empty()) return "not whole tets";
  for (double c : m.positions) {
    if (!std::isfinite(c)) return "a non-finite vertex read as ok";
  }
  for (size_t t = 0; t < m.tetCount(); ++t) {
    const uint32_t* v = &m.tets[4 * t];
    for (int a = 0; a < 4; ++a) {
      if (v[a] >= m.vertexCount()) return "a tet index names no vertex";
      for (int b = a + 1; b < 4; ++b) {
        if (v[a] == v[b]) return "a tet with a repeated vertex read as ok";
      }
    }
  }
  return "";
}

std::string checkProgram(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const ParsedProgram r = readProgram(text);
  if (std::string s = statusProblem(r); !s.empty()) return s;
  if (!r.ok()) return "";
  size_t lines = 1;
  for (char c : text) lines += c == '\n';
  int last = 0;
  for (const ProgramMove& m : r.moves) {
    if (m.line < 1 || size_t(m.line) > lines) return "a move names a line outside the text";
    if (m.line < last) return "moves out of line order";
    last = m.line;
  }
  if (r.layerCount < 0) return "negative layer count";
  return "";
}

// A profile that parses prints as JSON that parses to the same print (the page's machine editor
// and every program header rely on it).
std::string checkMachine(const uint8_t* data, size_t size) {
  const MachineParseResult r = machineFromJson(std::string(reinterpret_cast<const char*>(data), size));
  if (std::string s = statusProblem(r); !s.empty()) return s;
  if (!r.ok()) return "";
  const std::string json = machineJson(r.machine);
  const MachineParseResult again = machineFromJson(json);
  if (!again.ok()) return "a parsed profile's own JSON does not parse: " + again.message;
  if (machineJson(again.machine) != json) return "a parsed profile's JSON does not round-trip";
  return "";
}

// "key=value" lines as the CLI's --set and the wasm API give them: each is taken or refused with
// a message; the settings then list as text that, set again on defaults, lists the same.
std::string checkSettings(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  Settings s;
  size_t start = 0;
  while (start <= text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    const std::string line = text.substr(start, end - start);
    start = end + 1;
    const size_t eq = line.find('=');
    if (eq == std::string::npos) continue;
    const Outcome o = setSetting(s, line.substr(0, eq), line.substr(eq + 1));
    if (std::string p = statusProblem(o); !p.empty()) return "setSetting: " + p;
  }
  const Outcome v = validateSettings(s);
  if (std::string p = statusProblem(v); !p.empty()) return "validateSettings: " + p;
  const auto listed = listSettings(s);
  Settings t;
  for (const auto& [key, value] : listed) {
    const Outcome o = setSetting(t, key, value);
    if (!o.ok()) return "listed setting " + key + " = " + value + " does not set again: " + o.message;
  }
  if (listSettings(t) != listed) return "the listed settings do not round-trip";
  return "";
}

}  // namespace

const std::vector<Target>& targets() {
  static const std::vector<Target> all = {
      {"stl", &checkReader<kStl>}, {"obj", &checkReader<kObj>}, {"off", &checkReader<kOff>},
      {"ply", &checkReader<kPly>}, {"3mf", &checkReader<k3mf>}, {"inflate", &checkInflate},
      {"tet", &checkTet},             {"program", &checkProgram},       {"machine", &checkMachine},
      {"settings", &checkSettings},
  };
  return all;
}

const Target* findTarget(const std::string& name) {
  for (const Target& t : targets()) {
    if (name == t.name) return &t;
  }
  return nullptr;
}

}  // namespace omnislice::fuzz
