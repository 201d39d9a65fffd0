// SPDX-License-Identifier: MIT
// The preview's float32 buffers. GLM types here, and only here: float vectors and quaternions laid
// out as WebGL and three.js take them (glm::vec3 = 3 floats, glm::quat stores x y z w, as
// THREE.Quaternion.fromArray reads them; glm::dmat4 is column-major, as Eigen's default storage and
// THREE.Matrix4.elements). The core's geometry stays double (Eigen); it is narrowed once, here.
#include "pipeline/preview.h"

#include <algorithm>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "kinematics/kinematics.h"

namespace omnislice {
namespace {

glm::vec3 toFloat(const Eigen::Vector3d& v) { return glm::vec3(glm::dvec3(v.x(), v.y(), v.z())); }

void append(std::vector<float>& out, const glm::vec3& v) {
  const float* p = glm::value_ptr(v);
  out.insert(out.end(), p, p + 3);
}

// The platform poses of a preview: quaternion and translation per segment, each quaternion in
// the hemisphere of the one before.
class PoseBuffer {
 public:
  PoseBuffer(const MachineProfile& machine, std::vector<float>& out)
      : machine_(machine), out_(out), known_(machineAxisCount(machine.kind) > 0) {}

  // Appends the pose of `values`; where one has none (non-finite values), the buffer is cleared
  // and stays empty, so it is either complete or empty.
  void add(const MachineValues& values) {
    if (!known_) return;
    Eigen::Matrix4d t;
    if (!platformTransform(machine_, values, t)) {
      known_ = false;
      out_.clear();
      return;
    }
    glm::dmat4 m;
    std::copy(t.data(), t.data() + 16, glm::value_ptr(m));  // both column-major
    glm::dquat q = glm::quat_cast(glm::dmat3(m));
    q = glm::normalize(q);
    if (glm::dot(q, previous_) < 0) q = -q;
    previous_ = q;
    const glm::quat qf(q);
    const float* p = glm::value_ptr(qf);  // x y z w
    out_.insert(out_.end(), p, p + 4);
    append(out_, glm::vec3(glm::dvec3(m[3])));
  }

 private:
  const MachineProfile& machine_;
  std::vector<float>& out_;
  bool known_;
  glm::dquat previous_ = glm::dquat(1, 0, 0, 0);  // identity (the constructor takes w x y z)
};

}  // namespace

void appendPoint(std::vector<float>& out, const Eigen::Vector3d& p) { append(out, toFloat(p)); }

void appendFloats(std::vector<float>& out, const std::vector<double>& values) {
  out.reserve(out.size() + values.size());
  for (double v : values) out.push_back(static_cast<float>(v));
}

ToolpathPreview toolpathPreview(const MachinePath& path, const Toolpath& toolpath) {
  ToolpathPreview p;
  const size_t n = path.moves.size();
  p.positions.reserve(n * 6);
  p.features.reserve(n);
  p.layers.reserve(n);
  p.machine.reserve(n * 6);
  p.axes.reserve(n * 3);
  p.poses.reserve(n * 7);
  PoseBuffer poses(path.machine, p.poses);
  Eigen::Vector3d prev, prevAxis;
  if (!forwardMap(path.machine, path.start, prev, prevAxis)) prev = Eigen::Vector3d::Zero();
  for (const MachineMove& m : path.moves) {
    const bool draws = m.kind == MoveKind::Print || m.kind == MoveKind::Support ||
                       m.kind == MoveKind::Travel;
    if (draws && (m.tip - prev).squaredNorm() > 0) {
      append(p.positions, toFloat(prev));
      append(p.positions, toFloat(m.tip));
      p.features.push_back(m.kind == MoveKind::Travel ? 0 : static_cast<uint8_t>(m.feature));
      p.layers.push_back(static_cast<uint32_t>(std::max(0, m.layer)));
      for (double v : m.values) p.machine.push_back(static_cast<float>(v));
      append(p.axes, toFloat(m.axis));
      poses.add(m.values);
      p.curves.push_back(m.source < toolpath.moves.size() && m.kind != MoveKind::Travel
                             ? toolpath.moves[m.source].curve
                             : 0);
    }
    prev = m.tip;
  }
  return p;
}

ToolpathPreview programPreview(const ParsedProgram& program) {
  ToolpathPreview p;
  PoseBuffer poses(program.machine, p.poses);
  // Each feature marker's colour code: its Feature, WallInner for names that are none of them.
  std::vector<uint8_t> codes(program.features.size(), static_cast<uint8_t>(Feature::WallInner));
  for (size_t i = 0; i < program.features.size(); ++i) {
    for (uint8_t f = 1; f <= static_cast<uint8_t>(Feature::Bridge); ++f) {
      if (program.features[i] == featureName(static_cast<Feature>(f))) codes[i] = f;
    }
  }
  for (const ProgramMove& m : program.moves) {
    if ((m.to - m.from).squaredNorm() == 0) continue;  // retracts, pure rotations: no segment
    append(p.positions, toFloat(m.from));
    append(p.positions, toFloat(m.to));
    p.features.push_back(m.filament > 0 ? codes[m.feature] : 0);
    p.layers.push_back(static_cast<uint32_t>(std::max(0, m.layer)));
    MachineValues values{};
    for (size_t k = 0; k < 6; ++k) {
      values[k] = k < m.axes.size() ? m.axes[k] : 0.0;
      p.machine.push_back(static_cast<float>(values[k]));
    }
    poses.add(values);
  }
  return p;
}

}  // namespace omnislice
