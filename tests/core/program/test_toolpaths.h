// SPDX-License-Identifier: MIT
// Hand-built tool-paths for the writer, reader and verification tests (independent of the slicer):
// a solid box (two walls + zig-zag at 100 %) and a solid sphere (concentric rings).
#pragma once
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "toolpath/toolpath.h"

namespace omnislice::test {

class PathBuilder {
 public:
  PathBuilder(double layerHeight, double lineWidth) : h_(layerHeight), w_(lineWidth) {
    path.start = {0, 0, 5};
    pos_ = path.start;
  }
  Toolpath path;

  void setLayer(int layer) { layer_ = layer; }
  // Travel to p; retract first when the travel is longer than 2 mm.
  void travel(const Eigen::Vector3d& p) {
    const bool retract = (p - pos_).norm() > 2.0;
    if (retract) push(pos_, MoveKind::Retract, -0.8, 35, Feature::None);
    push(p, MoveKind::Travel, 0, 150, Feature::None);
    if (retract) push(p, MoveKind::Unretract, 0.8, 35, Feature::None);
  }
  void print(const Eigen::Vector3d& p, Feature f, double speed = 40) {
    const double area = M_PI * 0.25 * 1.75 * 1.75;
    push(p, f == Feature::Support ? MoveKind::Support : MoveKind::Print,
         w_ * h_ * (p - pos_).norm() / area, speed, f);
  }
  const Eigen::Vector3d& position() const { return pos_; }

 private:
  void push(const Eigen::Vector3d& p, MoveKind kind, double filament, double speed, Feature f) {
    Move m;
    m.position = p;
    m.kind = kind;
    m.filament = filament;
    m.speed = speed;
    m.feature = f;
    m.layer = layer_;
    if (kind == MoveKind::Print || kind == MoveKind::Support) {
      m.width = w_;
      m.height = h_;
    }
    path.moves.push_back(m);
    pos_ = p;
    path.layerCount = std::max(path.layerCount, layer_ + 1);
  }
  double h_, w_;
  int layer_ = 0;
  Eigen::Vector3d pos_;
};

// Closed rectangle loop [x0,x1]x[y0,y1] at height z.
inline void rectLoop(PathBuilder& b, double x0, double y0, double x1, double y1, double z, Feature f) {
  b.travel({x0, y0, z});
  b.print({x1, y0, z}, f);
  b.print({x1, y1, z}, f);
  b.print({x0, y1, z}, f);
  b.print({x0, y0, z}, f);
}

struct BoxPathOptions {
  double half = 5;         // box is [-half, half]^2 x [0, height]
  double height = 10;
  double h = 0.2;
  double w = 0.45;
  std::function<bool(int)> keepLayer;  // empty = all layers
  bool wallsOnly = false;
  bool infillOnly = false;
};

// Solid box at 100 %: per layer an outer and an inner wall, then zig-zag infill at spacing w,
// along X on even layers and along Y on odd ones. Centre-lines at the top of each layer.
inline Toolpath boxToolpath(const BoxPathOptions& o) {
  PathBuilder b(o.h, o.w);
  const int layers = int(std::lround(o.height / o.h));
  for (int l = 0; l < layers; ++l) {
    if (o.keepLayer && !o.keepLayer(l)) continue;
    b.setLayer(l);
    const double z = (l + 1) * o.h;
    if (!o.infillOnly) {
      const double a = o.half - 0.5 * o.w, c = o.half - 1.5 * o.w;
      rectLoop(b, -a, -a, a, a, z, Feature::WallOuter);
      rectLoop(b, -c, -c, c, c, z, Feature::WallInner);
    }
    if (o.wallsOnly) continue;
    const double lim = o.half - 2.5 * o.w;  // infill centre-lines span [-lim, lim]
    const int lines = int(std::floor(2 * lim / o.w)) + 1;
    const bool alongX = l % 2 == 0;
    for (int k = 0; k < lines; ++k) {
      const double t = -lim + k * (2 * lim / (lines - 1));
      const double s0 = (k % 2 == 0) ? -lim : lim, s1 = -s0;
      const Eigen::Vector3d p0 = alongX ? Eigen::Vector3d(s0, t, z) : Eigen::Vector3d(t, s0, z);
      const Eigen::Vector3d p1 = alongX ? Eigen::Vector3d(s1, t, z) : Eigen::Vector3d(t, s1, z);
      if (k == 0) b.travel(p0); else b.print(p0, Feature::Infill);
      b.print(p1, Feature::Infill);
    }
  }
  return b.path;
}

// Solid sphere of radius R resting on z = 0 (centre (0,0,R)): per layer concentric rings spaced w
// inward from the section at mid-layer, each ring a 2 mm-chord polygon.
inline Toolpath sphereToolpath(double R, double h, double w) {
  PathBuilder b(h, w);
  const int layers = int(std::lround(2 * R / h));
  for (int l = 0; l < layers; ++l) {
    b.setLayer(l);
    const double z = (l + 1) * h, zm = z - 0.5 * h;
    const double rs = std::sqrt(std::max(0.0, R * R - (zm - R) * (zm - R)));
    bool first = true;
    for (double r = rs - 0.5 * w; r > 0.25 * w; r -= w) {
      const int n = std::max(8, int(std::ceil(2 * M_PI * r / 1.0)));
      for (int k = 0; k <= n; ++k) {
        const double a = 2 * M_PI * k / n;
        const Eigen::Vector3d p(r * std::cos(a), r * std::sin(a), z);
        if (k == 0) {
          if (first) b.travel(p); else b.print(p, Feature::Infill);
        } else {
          b.print(p, first ? Feature::WallOuter : Feature::Infill);
        }
      }
      first = false;
    }
  }
  return b.path;
}

}  // namespace omnislice::test
