#include <gtest/gtest.h>
#include <fstream>
#include <cmath>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include "../test_support.h"
#include "pipeline/voxel_method.h"
#include "pipeline/pipeline.h"
#include "mesh/read_mesh.h"
#include "mesh/prepare_mesh.h"
#include "pipeline_fixtures.h"
#include "program/machine.h"
#include "geometry/aabb_tree.h"
#include "geometry/segment.h"
namespace omnislice {
std::vector<uint8_t> mushroomBytesDbg();
TEST(VoxelDebug, Collisions) {
  auto bytes = mushroomBytesDbg();
  ReadMeshResult rm = readMesh(bytes.data(), bytes.size(), "m.stl");
  PrepareMeshResult pm = prepareMesh(rm.mesh, PrepareOptions{});
  PlaceMeshResult pl = placeMesh(pm.mesh, PlacementSettings{});
  Settings s;
  setSetting(s, "method", "voxel"); setSetting(s, "machine", "table5");
  setSetting(s, "nozzle_diameter", "0.8"); setSetting(s, "layer_height", "0.6"); setSetting(s, "line_width", "0.9");
  MachineProfileResult mp = builtinMachine("table5", s.bedSize, 0.8);
  VoxelMethodOutput v = runVoxelMethod(pl.mesh, s, mp.machine, {});
  ASSERT_TRUE(v.ok()) << v.message;
  printf("%s\n", v.reportJson.c_str());
  // samples
  struct S { Eigen::Vector3d p, u; int layer; size_t move; };
  std::vector<S> samples;
  Eigen::Vector3d prev = v.toolpath.start;
  for (size_t i = 0; i < v.toolpath.moves.size(); ++i) {
    const Move& m = v.toolpath.moves[i];
    if (m.kind == MoveKind::Print || m.kind == MoveKind::Support) {
      double len = (m.position - prev).norm();
      int n = std::max(1, int(len / 0.5));
      for (int k = 0; k < n; ++k) samples.push_back({prev + (m.position - prev) * (double(k) / n), m.axis, m.layer, i});
    }
    prev = m.position;
  }
  const double h = v.layerHeight, half = 40 * M_PI / 180;
  std::map<int, int> perLayer; std::map<int,int> tot;
  int shown = 0;
  for (size_t a = 0; a < samples.size(); ++a) {
    tot[samples[a].layer]++;
    for (size_t b = 0; b < a; ++b) {
      Eigen::Vector3d d = samples[b].p - samples[a].p;
      double ax = d.dot(samples[a].u);
      if (ax <= h + 1e-3) continue;
      double ang = std::acos(std::clamp(ax / d.norm(), -1.0, 1.0));
      if (ang < half && d.norm() < 25) {
        perLayer[samples[a].layer]++;
        if (shown++ < 10) printf("collide: s layer %d at (%.2f %.2f %.2f) u (%.2f %.2f %.2f) with p layer %d at (%.2f %.2f %.2f), ax %.3f\n",
          samples[a].layer, samples[a].p.x(), samples[a].p.y(), samples[a].p.z(), samples[a].u.x(), samples[a].u.y(), samples[a].u.z(),
          samples[b].layer, samples[b].p.x(), samples[b].p.y(), samples[b].p.z(), ax);
        break;
      }
    }
  }
  printf("h %.3f samples %zu\n", h, samples.size());
  for (auto [l, c] : tot) printf("layer %d: %d samples, %d colliding\n", l, c, perLayer[l]);
}
}
namespace omnislice {
TEST(VoxelDebug, Paths) {
  auto bytes = mushroomBytesDbg();
  Settings s;
  setSetting(s, "method", "voxel"); setSetting(s, "machine", "table5");
  setSetting(s, "nozzle_diameter", "0.8"); setSetting(s, "layer_height", "0.6"); setSetting(s, "line_width", "0.9");
  SliceOutput out = runSlice(bytes.data(), bytes.size(), "m.stl", s);
  ASSERT_TRUE(out.ok()) << out.message;
  auto r = nlohmann::json::parse(out.reportJson);
  printf("report path %.1f extrusion %.1f moves %d motion %s\n", r["path_mm"].get<double>(), r["extrusion_mm"].get<double>(), r["moves"].get<int>(), r["motion"].dump().c_str());
  FILE* f = fopen("/tmp/mushroom.gcode", "w"); fwrite(out.program.data(), 1, out.program.size(), f); fclose(f);
  f = fopen("/tmp/mushroom.stl", "wb"); fwrite(bytes.data(), 1, bytes.size(), f); fclose(f);
}
}
#include "motion/plan_motion.h"
#include "program/read_program.h"
#include "toolpath/toolpath.h"
namespace omnislice {
TEST(VoxelDebug, Motion) {
  auto bytes = mushroomBytesDbg();
  ReadMeshResult rm = readMesh(bytes.data(), bytes.size(), "m.stl");
  PrepareMeshResult pm = prepareMesh(rm.mesh, PrepareOptions{});
  PlaceMeshResult pl = placeMesh(pm.mesh, PlacementSettings{});
  Settings s;
  setSetting(s, "method", "voxel"); setSetting(s, "machine", "table5");
  setSetting(s, "nozzle_diameter", "0.8"); setSetting(s, "layer_height", "0.6"); setSetting(s, "line_width", "0.9");
  MachineProfileResult mp = builtinMachine("table5", s.bedSize, 0.8);
  VoxelMethodOutput v = runVoxelMethod(pl.mesh, s, mp.machine, {});
  ToolpathStats st = toolpathStats(v.toolpath, 0);
  MachinePath path = planMachineMotion(v.toolpath, mp.machine, MotionOptions{}, {});
  ASSERT_TRUE(path.ok()) << path.message;
  double len = 0; Eigen::Vector3d prev = Eigen::Vector3d::Zero(); bool have = false;
  for (const MachineMove& m : path.moves) {
    if (have && (m.kind == MoveKind::Print || m.kind == MoveKind::Support)) len += (m.tip - prev).norm();
    prev = m.tip; have = true;
  }
  printf("toolpath path %.1f machine path tips %.1f\n", st.pathMm, len);
  // replay the written program
  std::ifstream in("/tmp/mushroom.gcode"); std::string text((std::istreambuf_iterator<char>(in)), {});
  ParsedProgram pp = readProgram(text);
  ASSERT_TRUE(pp.ok()) << pp.message;
  double rl = 0; int big = 0;
  for (size_t i = 0; i < pp.moves.size(); ++i) {
    const auto& b = pp.moves[i];
    if (b.filament > 0) { double d = (b.to - b.from).norm(); rl += d; if (d > 3 && big++ < 8) printf("long extruding replay move line %d: %.2f mm from (%.2f %.2f %.2f) to (%.2f %.2f %.2f) E %.4f\n", b.line, d, b.from.x(), b.from.y(), b.from.z(), b.to.x(), b.to.y(), b.to.z(), b.filament); }
  }
  printf("replay path %.1f\n", rl);
  std::map<int, std::pair<double, Eigen::Vector3d>> perLine; std::map<int, Eigen::Vector3d> firstFrom, lastTo;
  for (const auto& b : pp.moves) {
    if (b.filament <= 0) continue;
    perLine[b.line].first += (b.to - b.from).norm();
    if (!firstFrom.count(b.line)) firstFrom[b.line] = b.from;
    lastTo[b.line] = b.to;
  }
  double extra = 0; int shown = 0;
  for (auto& [line, v] : perLine) {
    double straight = (lastTo[line] - firstFrom[line]).norm();
    extra += v.first - straight;
    if (v.first - straight > 0.3 && shown++ < 10) printf("line %d: replay %.3f straight %.3f\n", line, v.first, straight);
  }
  printf("extra %.1f over %zu lines\n", extra, perLine.size());
}
}
namespace omnislice {
TEST(VoxelDebug, Supported) {
  auto bytes = mushroomBytesDbg();
  ReadMeshResult rm = readMesh(bytes.data(), bytes.size(), "m.stl");
  PrepareMeshResult pm = prepareMesh(rm.mesh, PrepareOptions{});
  PlaceMeshResult pl = placeMesh(pm.mesh, PlacementSettings{});
  Settings s;
  setSetting(s, "method", "voxel"); setSetting(s, "machine", "table5");
  setSetting(s, "nozzle_diameter", "0.8"); setSetting(s, "layer_height", "0.6"); setSetting(s, "line_width", "0.9");
  MachineProfileResult mp = builtinMachine("table5", s.bedSize, 0.8);
  VoxelMethodOutput v = runVoxelMethod(pl.mesh, s, mp.machine, {});
  AabbTree tree(pl.mesh);
  struct Seg { Eigen::Vector3d a, b; double along; int layer; };
  std::vector<Seg> segs; Eigen::Vector3d prev = v.toolpath.start; double along = 0;
  for (const Move& m : v.toolpath.moves) {
    if (m.kind == MoveKind::Print) { segs.push_back({prev, m.position, along, m.layer}); along += (m.position - prev).norm(); }
    prev = m.position;
  }
  const double h = v.layerHeight, w = 0.9;
  std::map<int, int> bad, tot; int shown = 0;
  for (size_t i = 0; i < segs.size(); ++i) {
    const Seg& sg = segs[i];
    double len = (sg.b - sg.a).norm(); int n = std::max(1, int(len / 0.5));
    for (int k = 0; k < n; ++k) {
      Eigen::Vector3d p = sg.a + (sg.b - sg.a) * (double(k) / n);
      double pAlong = sg.along + len * k / n;
      if (tree.closest(p, w).distance > w) continue;
      tot[sg.layer]++;
      bool ok = p.z() <= 1.5 * h;
      for (size_t j = 0; j < i && !ok; ++j) {
        if (segs[j].along + (segs[j].b - segs[j].a).norm() > pAlong - std::max(0.5, 3 * h)) break;
        if (std::sqrt(pointSegmentDistance2(p, segs[j].a, segs[j].b)) <= 1.5 * h) ok = true;
      }
      if (!ok) { bad[sg.layer]++; if (shown++ < 8) printf("unsupported layer %d at (%.2f %.2f %.2f)\n", sg.layer, p.x(), p.y(), p.z()); }
    }
  }
  for (auto [l, c] : tot) printf("layer %d: %d surface samples, %d unsupported\n", l, c, bad[l]);
}
}
