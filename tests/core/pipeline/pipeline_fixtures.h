// SPDX-License-Identifier: MIT
// Fixtures for pipeline and CLI tests: meshes as file bytes (the meshes are in test_meshes.h).
#pragma once
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "mesh/mesh.h"
#include "pipeline/settings.h"

namespace omnislice::test {

// Binary STL bytes of a mesh (80-byte header, count, 50 bytes per face).
inline std::vector<uint8_t> binaryStl(const Mesh& m, const std::string& header = "omnislice test") {
  std::vector<uint8_t> out(84 + 50 * m.faceCount(), 0);
  std::memcpy(out.data(), header.data(), std::min<size_t>(header.size(), 80));
  const uint32_t n = static_cast<uint32_t>(m.faceCount());
  std::memcpy(out.data() + 80, &n, 4);
  for (size_t f = 0; f < m.faceCount(); ++f) {
    uint8_t* rec = out.data() + 84 + 50 * f;
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = m.triangles[3 * f + k];
      for (int c = 0; c < 3; ++c) {
        const float x = static_cast<float>(m.positions[3 * v + c]);
        std::memcpy(rec + 12 + 12 * k + 4 * c, &x, 4);
      }
    }
  }
  return out;
}

// A curved-layer method on table5 with 0.8 mm beads, 0.6 mm layers, 0.9 mm lines; the program is
// delivered whatever the check finds (verify = warn) and made once (the tests judge it).
inline Settings coarseCurvedSettings(Method method) {
  Settings s;
  s.method = method;
  s.machine = "table5";
  s.nozzleDiameter = 0.8;
  s.layerHeight = 0.6;
  s.lineWidth = 0.9;
  s.verify = VerifyMode::Warn;
  s.verifyAttempts = 1;
  return s;
}

// A report's JSON without what depends on the clock (timings_ms, ms, *_ms), to compare runs.
inline nlohmann::json timelessReport(const nlohmann::json& j) {
  if (j.is_object()) {
    nlohmann::json out = nlohmann::json::object();
    for (const auto& [k, v] : j.items()) {
      if (k == "timings_ms" || k == "ms" || (k.size() > 3 && k.compare(k.size() - 3, 3, "_ms") == 0)) continue;
      out[k] = timelessReport(v);
    }
    return out;
  }
  if (j.is_array()) {
    nlohmann::json out = nlohmann::json::array();
    for (const nlohmann::json& v : j) out.push_back(timelessReport(v));
    return out;
  }
  return j;
}

}  // namespace omnislice::test
