// SPDX-License-Identifier: MIT
#include "pipeline/preview.h"

#include <algorithm>

#include "kinematics/kinematics.h"

namespace omnislice {

ToolpathPreview toolpathPreview(const MachinePath& path, const Toolpath& toolpath) {
  ToolpathPreview p;
  const size_t n = path.moves.size();
  p.positions.reserve(n * 6);
  p.features.reserve(n);
  p.layers.reserve(n);
  p.machine.reserve(n * 6);
  p.axes.reserve(n * 3);
  Eigen::Vector3d prev, prevAxis;
  if (!forwardMap(path.machine, path.start, prev, prevAxis)) prev = Eigen::Vector3d::Zero();
  for (const MachineMove& m : path.moves) {
    const bool draws = m.kind == MoveKind::Print || m.kind == MoveKind::Support ||
                       m.kind == MoveKind::Travel;
    if (draws && (m.tip - prev).squaredNorm() > 0) {
      for (const Eigen::Vector3d& q : {prev, m.tip}) {
        p.positions.push_back(static_cast<float>(q.x()));
        p.positions.push_back(static_cast<float>(q.y()));
        p.positions.push_back(static_cast<float>(q.z()));
      }
      p.features.push_back(m.kind == MoveKind::Travel ? 0 : static_cast<uint8_t>(m.feature));
      p.layers.push_back(static_cast<uint32_t>(std::max(0, m.layer)));
      for (double v : m.values) p.machine.push_back(static_cast<float>(v));
      for (int k = 0; k < 3; ++k) p.axes.push_back(static_cast<float>(m.axis[k]));
      p.curves.push_back(m.source < toolpath.moves.size() && m.kind != MoveKind::Travel
                             ? toolpath.moves[m.source].curve
                             : 0);
    }
    prev = m.tip;
  }
  return p;
}

}  // namespace omnislice
