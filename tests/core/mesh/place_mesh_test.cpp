// SPDX-License-Identifier: MIT
// placeMesh: fit, up axis, rotations, drop to z = 0, centring; the transform reproduces the
// vertices; volume scales by s^3 and stays positive (never a mirror).
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "test_meshes.h"
#include "mesh/place_mesh.h"
#include "mesh/prepare_mesh.h"
#include "test_support.h"

namespace omnislice {
namespace {

// Asserts the placement invariants and returns the placed bounding box.
BoundingBox checkPlacement(const Mesh& in, const PlaceOptions& p, double expectedScale) {
  const PlaceMeshResult r = placeMesh(in, p);
  EXPECT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(r.mesh.triangles, in.triangles);
  const BoundingBox inBox = boundingBox(in);
  const double size = (inBox.max - inBox.min).norm() * expectedScale + 1;
  for (size_t i = 0; i < in.vertexCount(); ++i) {
    const Eigen::Vector4d q = r.transform * in.vertex(i).homogeneous();
    EXPECT_LT((q.head<3>() - r.mesh.vertex(i)).norm(), 1e-12 * size) << "vertex " << i;
  }
  EXPECT_EQ(r.transform.row(3), Eigen::RowVector4d(0, 0, 0, 1));
  const Eigen::Matrix3d L = r.transform.topLeftCorner<3, 3>();
  EXPECT_NEAR(L.determinant(), std::pow(expectedScale, 3), 1e-9 * std::pow(expectedScale, 3));
  EXPECT_LT((L.transpose() * L - expectedScale * expectedScale * Eigen::Matrix3d::Identity()).norm(),
            1e-12 * expectedScale * expectedScale);
  const BoundingBox box = boundingBox(r.mesh);
  EXPECT_EQ(box.min.z(), 0.0);
  if (p.center) {
    EXPECT_NEAR(box.min.x() + box.max.x(), 0, 1e-12 * size);
    EXPECT_NEAR(box.min.y() + box.max.y(), 0, 1e-12 * size);
  }
  const double v0 = test::meshVolume(in), v1 = test::meshVolume(r.mesh);
  EXPECT_NEAR(v1, v0 * std::pow(expectedScale, 3), 1e-9 * std::abs(v1));
  if (v0 > 0) {
    EXPECT_GT(v1, 0);
  }
  return box;
}

TEST(PlaceMesh, DefaultDropsAndCentres) {
  const Mesh box = test::makeBox(10, 20, 30, 11, 22, 33);
  const BoundingBox b = checkPlacement(box, {}, 1.0);
  EXPECT_EQ(b.min, Eigen::Vector3d(-0.5, -1, 0));
  EXPECT_EQ(b.max, Eigen::Vector3d(0.5, 1, 3));
}

TEST(PlaceMesh, KeepsXYWhenNotCentred) {
  const Mesh box = test::makeBox(10, 20, -5, 11, 22, 33);
  PlaceOptions p;
  p.center = false;
  const PlaceMeshResult r = placeMesh(box, p);
  ASSERT_TRUE(r.ok());
  for (size_t i = 0; i < box.vertexCount(); ++i) {
    EXPECT_EQ(r.mesh.vertex(i).x(), box.vertex(i).x());
    EXPECT_EQ(r.mesh.vertex(i).y(), box.vertex(i).y());
    EXPECT_EQ(r.mesh.vertex(i).z(), box.vertex(i).z() + 5);
  }
  checkPlacement(box, p, 1.0);
}

TEST(PlaceMesh, ScaleAndFit) {
  const Mesh box = test::makeBox(0, 0, 0, 1, 2, 4);
  PlaceOptions p;
  p.scale = 2.5;
  BoundingBox b = checkPlacement(box, p, 2.5);
  EXPECT_NEAR(b.max.z(), 10, 1e-12);
  p.fitMm = 100;  // overrides scale: the largest side (z, 4) becomes 100
  b = checkPlacement(box, p, 25);
  EXPECT_NEAR((b.max - b.min).maxCoeff(), 100, 1e-12);
  EXPECT_NEAR(b.max.x() - b.min.x(), 25, 1e-12);
  EXPECT_NEAR(b.max.y() - b.min.y(), 50, 1e-12);
}

// Up axis: the named input axis ends up pointing along +Z, by a rotation.
TEST(PlaceMesh, UpAxis) {
  // An asymmetric solid: a tall box along +Y with a small bump at its +Y end.
  const Mesh m = test::append(test::makeBox(0, 0, 0, 2, 10, 3), test::makeBox(0.5, 10, 0.5, 1.0, 11, 1.0));
  const Eigen::Vector3d bumpIn(0.75, 10.5, 0.75);
  struct Case {
    UpAxis up;
    Eigen::Vector3d axis;
  };
  for (const Case& c : {Case{UpAxis::PosZ, {0, 0, 1}}, Case{UpAxis::NegZ, {0, 0, -1}},
                        Case{UpAxis::PosY, {0, 1, 0}}, Case{UpAxis::NegY, {0, -1, 0}},
                        Case{UpAxis::PosX, {1, 0, 0}}, Case{UpAxis::NegX, {-1, 0, 0}}}) {
    PlaceOptions p;
    p.up = c.up;
    checkPlacement(m, p, 1.0);
    const PlaceMeshResult r = placeMesh(m, p);
    const Eigen::Matrix3d L = r.transform.topLeftCorner<3, 3>();
    EXPECT_LT((L * c.axis - Eigen::Vector3d::UnitZ()).norm(), 1e-15);
    // Heights follow the chosen axis: the bump (max +Y) is on top for PosY, at the bottom for NegY.
    const double bumpZ = (r.transform * bumpIn.homogeneous()).z();
    const BoundingBox b = boundingBox(r.mesh);
    if (c.up == UpAxis::PosY) {
      EXPECT_NEAR(bumpZ, 10.5, 1e-12);
    }
    if (c.up == UpAxis::NegY) {
      EXPECT_NEAR(bumpZ, 0.5, 1e-12);
    }
    if (c.up == UpAxis::PosY || c.up == UpAxis::NegY) {
      EXPECT_NEAR(b.max.z(), 11, 1e-12);
    }
  }
}

// Rotations about part X, then Y, then Z, after the up-axis change.
TEST(PlaceMesh, Rotations) {
  const Mesh box = test::makeBox(0, 0, 0, 1, 2, 3);
  PlaceOptions p;
  p.rotateXDegrees = 90;  // y -> z
  BoundingBox b = checkPlacement(box, p, 1.0);
  EXPECT_NEAR(b.max.x() - b.min.x(), 1, 1e-12);
  EXPECT_NEAR(b.max.y() - b.min.y(), 3, 1e-12);
  EXPECT_NEAR(b.max.z(), 2, 1e-12);
  p.rotateXDegrees = 0;
  p.rotateYDegrees = 90;  // x -> -z
  b = checkPlacement(box, p, 1.0);
  EXPECT_NEAR(b.max.z(), 1, 1e-12);
  EXPECT_NEAR(b.max.x() - b.min.x(), 3, 1e-12);

  // Order: X first, then Y, then Z (rotations about the fixed part axes).
  p.rotateXDegrees = 30;
  p.rotateYDegrees = 45;
  p.rotateZDegrees = -60;
  p.up = UpAxis::PosY;
  p.scale = 1.7;
  const PlaceMeshResult r = placeMesh(test::makeIcosphere(5, 2, {1, 2, 3}), p);
  ASSERT_TRUE(r.ok());
  const double d = M_PI / 180;
  const Eigen::Matrix3d expected =
      1.7 * (Eigen::AngleAxisd(-60 * d, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(45 * d, Eigen::Vector3d::UnitY()) *
             Eigen::AngleAxisd(30 * d, Eigen::Vector3d::UnitX()) * Eigen::AngleAxisd(90 * d, Eigen::Vector3d::UnitX()))
                .toRotationMatrix();
  EXPECT_LT((r.transform.topLeftCorner<3, 3>() - expected).norm(), 1e-12);
  checkPlacement(test::makeIcosphere(5, 2, {1, 2, 3}), p, 1.7);
  // A prepared (outward) mesh stays outward through any placement.
  const PrepareMeshResult prepared = prepareMesh(r.mesh, {});
  EXPECT_GT(prepared.info.volumeMm3, 0);
}

TEST(PlaceMesh, InvalidOptions) {
  const Mesh box = test::makeBox(0, 0, 0, 1, 1, 1);
  auto status = [&](auto edit) {
    PlaceOptions p;
    edit(p);
    return placeMesh(box, p).status;
  };
  EXPECT_EQ(status([](PlaceOptions& p) { p.scale = 0; }), Status::InvalidOption);
  EXPECT_EQ(status([](PlaceOptions& p) { p.scale = -2; }), Status::InvalidOption);
  EXPECT_EQ(status([](PlaceOptions& p) { p.scale = NAN; }), Status::InvalidOption);
  EXPECT_EQ(status([](PlaceOptions& p) { p.scale = INFINITY; }), Status::InvalidOption);
  EXPECT_EQ(status([](PlaceOptions& p) { p.fitMm = -1; }), Status::InvalidOption);
  EXPECT_EQ(status([](PlaceOptions& p) { p.fitMm = NAN; }), Status::InvalidOption);
  EXPECT_EQ(status([](PlaceOptions& p) { p.rotateYDegrees = INFINITY; }), Status::InvalidOption);
  EXPECT_EQ(placeMesh(test::makeBox(0, 0, 0, 10, 10, 10), PlaceOptions{1e308}).status, Status::InvalidOption);
  EXPECT_EQ(placeMesh(Mesh{}, {}).status, Status::EmptyInput);
}

}  // namespace
}  // namespace omnislice
