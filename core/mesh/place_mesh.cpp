// SPDX-License-Identifier: MIT
// placeMesh: scale, up-axis change, rotations and the drop onto the platform.
#include "mesh/place_mesh.h"

#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "common/math_constants.h"

namespace omnislice {
namespace {

PlaceMeshResult invalid(Status status, std::string message) {
  PlaceMeshResult r;
  r.status = status;
  r.message = std::move(message);
  r.transform.setIdentity();
  return r;
}

// Proper rotation taking the named input axis to +Z (determinant +1, never a mirror).
Eigen::Matrix3d upAxisRotation(UpAxis up) {
  const double halfPi = kPi / 2;
  switch (up) {
    case UpAxis::PosZ: return Eigen::Matrix3d::Identity();
    case UpAxis::NegZ: return Eigen::AngleAxisd(kPi, Eigen::Vector3d::UnitX()).toRotationMatrix();
    case UpAxis::PosY: return Eigen::AngleAxisd(halfPi, Eigen::Vector3d::UnitX()).toRotationMatrix();
    case UpAxis::NegY: return Eigen::AngleAxisd(-halfPi, Eigen::Vector3d::UnitX()).toRotationMatrix();
    case UpAxis::PosX: return Eigen::AngleAxisd(-halfPi, Eigen::Vector3d::UnitY()).toRotationMatrix();
    case UpAxis::NegX: return Eigen::AngleAxisd(halfPi, Eigen::Vector3d::UnitY()).toRotationMatrix();
  }
  return Eigen::Matrix3d::Identity();
}

// Rounding leaves 6.1e-17 where a quarter turn should give 0; snap those so that axis-aligned
// placements keep axis-aligned coordinates exactly.
Eigen::Matrix3d snapRotation(Eigen::Matrix3d r) {
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (std::abs(r(i, j)) < 1e-15) r(i, j) = 0;
      if (std::abs(std::abs(r(i, j)) - 1) < 1e-15) r(i, j) = r(i, j) > 0 ? 1 : -1;
    }
  }
  return r;
}

}  // namespace

PlaceMeshResult placeMesh(const Mesh& mesh, const PlaceOptions& placement) {
  const PlaceOptions& p = placement;
  if (!std::isfinite(p.scale) || !(p.scale > 0)) {
    return invalid(Status::InvalidOption, "placement scale must be a finite value > 0");
  }
  if (!std::isfinite(p.fitMm) || p.fitMm < 0) {
    return invalid(Status::InvalidOption, "placement fit_mm must be a finite value >= 0 (0 = off)");
  }
  if (!std::isfinite(p.rotateXDegrees) || !std::isfinite(p.rotateYDegrees) ||
      !std::isfinite(p.rotateZDegrees)) {
    return invalid(Status::InvalidOption, "placement rotations must be finite (degrees)");
  }
  if (mesh.vertexCount() == 0) return invalid(Status::EmptyInput, "the mesh has no vertices");
  for (double v : mesh.positions) {
    if (!std::isfinite(v)) return invalid(Status::NonFiniteVertex, "the mesh has a non-finite coordinate");
  }

  double scale = p.scale;
  if (p.fitMm > 0) {
    const BoundingBox box = boundingBox(mesh);
    const double largest = (box.max - box.min).maxCoeff();
    if (!(largest > 0)) {
      return invalid(Status::DegenerateInput, "cannot fit a mesh of zero size to " +
                                                  std::to_string(p.fitMm) + " mm");
    }
    scale = p.fitMm / largest;
  }
  const double degree = kPi / 180;
  const Eigen::Matrix3d rotation =
      snapRotation(Eigen::AngleAxisd(p.rotateZDegrees * degree, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
                   Eigen::AngleAxisd(p.rotateYDegrees * degree, Eigen::Vector3d::UnitY()).toRotationMatrix() *
                   Eigen::AngleAxisd(p.rotateXDegrees * degree, Eigen::Vector3d::UnitX()).toRotationMatrix() *
                   upAxisRotation(p.up));
  const Eigen::Matrix3d linear = scale * rotation;

  PlaceMeshResult result;
  result.mesh.triangles = mesh.triangles;
  result.mesh.positions.resize(mesh.positions.size());
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
  for (size_t i = 0; i < mesh.vertexCount(); ++i) {
    const Eigen::Vector3d q = linear * mesh.vertex(i);
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
    for (int k = 0; k < 3; ++k) result.mesh.positions[3 * i + k] = q[k];
  }
  Eigen::Vector3d shift(0, 0, -lo.z());
  if (p.center) {
    shift.x() = -0.5 * (lo.x() + hi.x());
    shift.y() = -0.5 * (lo.y() + hi.y());
  }
  for (size_t i = 0; i < mesh.vertexCount(); ++i) {
    for (int k = 0; k < 3; ++k) result.mesh.positions[3 * i + k] += shift[k];
  }
  result.transform.setIdentity();
  result.transform.topLeftCorner<3, 3>() = linear;
  result.transform.topRightCorner<3, 1>() = shift;
  for (double v : result.mesh.positions) {
    if (!std::isfinite(v)) return invalid(Status::InvalidOption, "placement overflows the coordinate range");
  }
  return result;
}

}  // namespace omnislice
