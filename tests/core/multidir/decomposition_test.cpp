// SPDX-License-Identifier: MIT
// searchDecomposition / evaluateDecomposition (paper 000): synthetic solids with a known optimum
// (an L-bracket and a T, built here as closed box unions), each criterion, each scheme, the 4dof
// normal grid, J_G exact against a brute-force subdivision, bad options and cancellation, and the
// shared closed models (beam <= both greedy schemes; numbers and timings printed, not asserted).
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "common/math_constants.h"
#include "mesh/place_mesh.h"
#include "mesh/prepare_mesh.h"
#include "multidir/decomposition.h"
#include "test_meshes.h"
#include "test_support.h"

namespace omnislice {
namespace {

// The scheme of a name as the search's progress lines call it.
SearchScheme schemeNamed(const std::string& name) {
  for (SearchScheme s : {SearchScheme::Greedy, SearchScheme::Constrained, SearchScheme::Beam}) {
    if (name == searchSchemeName(s)) return s;
  }
  ADD_FAILURE() << "no scheme " << name;
  return SearchScheme::Beam;
}


using test::Box;
using test::makeBoxUnion;
using test::makeLBracket;

// makeLBracket(20): column [0,20]^2 x [0,60] with an arm [20,60] x [0,20] x [40,60]; the arm's
// underside (800 mm^2 at z = 40) is the only risky area along +Z.

// T: the same column with a bar [-40,60] x [0,20] x [40,60]: two overhangs of 800 mm^2.
Mesh makeT() { return makeBoxUnion({{0, 0, 0, 20, 20, 60}, {-40, 0, 40, 60, 20, 60}}); }
// Arch with a pendant: columns x in [0,10] and [40,50], bridge [0,50] x z [40,50], pendant
// [20,30] x z [5,40] hanging from the bridge (y in [0,10] throughout).
Mesh makeArchPendant() {
  return makeBoxUnion({{0, 0, 0, 10, 10, 40}, {40, 0, 0, 50, 10, 40}, {0, 0, 40, 50, 10, 50},
                       {20, 0, 5, 30, 10, 40}});
}

bool above(const MultidirPlane& p, const Eigen::Vector3d& x) { return p.normal.dot(x) > p.offsetMm; }

// Independent J_G: every face split into s^2 sub-triangles, each given whole to the part its
// centroid falls in (first plane it is above), risky by Eq. 1 along that part's direction; the
// platform part skips faces whose centroid is below the band.
double bruteForceJg(const Mesh& mesh, const std::vector<MultidirPlane>& planes, double alphaDeg,
                    double band, int s) {
  const double sa = std::sin(alphaDeg * kPi / 180);
  double jg = 0;
  for (size_t f = 0; f < mesh.faceCount(); ++f) {
    const Eigen::Vector3d a = mesh.vertex(mesh.triangles[3 * f]), b = mesh.vertex(mesh.triangles[3 * f + 1]),
                          c = mesh.vertex(mesh.triangles[3 * f + 2]);
    const Eigen::Vector3d cr = (b - a).cross(c - a);
    if (cr.norm() == 0) continue;
    const Eigen::Vector3d n = cr.normalized();
    const double faceCz = (a.z() + b.z() + c.z()) / 3;
    const double subArea = cr.norm() / 2 / (s * s);
    auto at = [&](double u, double v) { return a + u / s * (b - a) + v / s * (c - a); };
    auto add = [&](const Eigen::Vector3d& centroid) {
      for (const MultidirPlane& p : planes) {
        if (above(p, centroid)) {
          if (n.dot(p.normal.normalized()) + sa < 0) jg += subArea;
          return;
        }
      }
      if (n.z() + sa < 0 && !(faceCz < band)) jg += subArea;
    };
    for (int i = 0; i < s; ++i) {
      for (int j = 0; i + j < s; ++j) {
        add((at(i, j) + at(i + 1, j) + at(i, j + 1)) / 3);
        if (i + j + 1 < s) add((at(i + 1, j) + at(i + 1, j + 1) + at(i, j + 1)) / 3);
      }
    }
  }
  return jg;
}

void printResult(const char* name, const MultidirResult& r) {
  std::printf("  %-34s %-11s J_G %9.2f -> %8.2f (ratio %.4f), parts %zu, %7.1f ms (sweep %.1f, checks %.1f), "
              "candidates %zu, checked %zu, floods %zu, beams %zu, levels %zu\n",
              name, "", r.jgBeforeMm2, r.jgAfterMm2, r.jgBeforeMm2 > 0 ? r.jgAfterMm2 / r.jgBeforeMm2 : 0.0,
              r.parts.size(), r.stats.msTotal, r.stats.msSweep, r.stats.msChecks, r.stats.candidatesEvaluated,
              r.stats.candidatesChecked, r.stats.connectivityChecks, r.stats.beams, r.stats.levels);
}

// Every plane of a result passes Criteria II-IV in the independent re-evaluation, and the
// reported J_G is the exact one.
void expectValid(const Mesh& mesh, const MultidirResult& r, const MultidirOptions& o, const std::string& what) {
  const MultidirEvaluation e = evaluateDecomposition(mesh, r.planes, o);
  ASSERT_TRUE(e.ok()) << what << ": " << e.message;
  EXPECT_NEAR(e.jgAfterMm2, r.jgAfterMm2, 1e-6 * (1 + r.jgBeforeMm2)) << what;
  EXPECT_EQ(r.parts.size(), r.planes.size() + 1) << what;
  for (size_t k = 0; k < e.checks.size(); ++k) {
    EXPECT_TRUE(e.checks[k].platformBelow) << what << ": plane " << k << " has the platform above";
    EXPECT_TRUE(e.checks[k].connected) << what << ": plane " << k << " leaves a floating piece";
    EXPECT_TRUE(e.checks[k].partLargeEnough) << what << ": plane " << k << " cuts a part < V/w";
  }
  ASSERT_EQ(r.stats.jgPerLevel.size(), r.planes.size() + 1) << what;
  EXPECT_NEAR(r.stats.jgPerLevel.back(), r.jgAfterMm2, 1e-6 * (1 + r.jgBeforeMm2)) << what;
  EXPECT_NEAR(r.stats.jgPerLevel.front(), r.jgBeforeMm2, 1e-6 * (1 + r.jgBeforeMm2)) << what;
  // The search's own sums (prefix sums with closed-form straddling areas) equal the exact
  // clipping; refinement only ever lowers J_G.
  if (!o.refine) {
    EXPECT_NEAR(r.stats.searchJgMm2, r.jgAfterMm2, 1e-6 * (1 + r.jgBeforeMm2)) << what;
  }
  EXPECT_LE(r.jgAfterMm2, r.stats.searchJgMm2 + 1e-6 * (1 + r.jgBeforeMm2)) << what;
}

// ---- synthetic solids with a known optimum -----------------------------------------------------

TEST(DecompSynthetic, BoxUnionIsClosedAndOutward) {
  const Mesh l = makeLBracket(20);
  EXPECT_NEAR(test::meshVolume(l), 20 * 20 * 60 + 40 * 20 * 20, 1e-9);
  const PrepareMeshResult p = prepareMesh(l, {});
  ASSERT_TRUE(p.ok());
  EXPECT_TRUE(p.info.closed && p.info.manifold && p.info.oriented);
  EXPECT_TRUE(p.info.repairs.empty()) << p.info.repairs.front();
}

TEST(DecompSynthetic, BoxHasNoRiskyFaceOnThePlatform) {
  // The bottom face faces down but rests on the platform (band), so J_G = 0 and no plane is cut.
  const MultidirResult r = searchDecomposition(test::makeBox(0, 0, 0, 30, 20, 10));
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(r.jgBeforeMm2, 0);
  EXPECT_TRUE(r.planes.empty());
  EXPECT_EQ(r.parts.size(), 1u);
}

TEST(DecompSynthetic, LBracketOneCutSeparatesTheOverhang) {
  const Mesh l = makeLBracket(20);
  MultidirOptions o;
  o.platformMarginMm = 2;
  const MultidirResult r = searchDecomposition(l, o);
  ASSERT_TRUE(r.ok()) << r.message;
  printResult("L-bracket beam", r);
  EXPECT_NEAR(r.jgBeforeMm2, 800, 1e-9);
  EXPECT_NEAR(r.jgAfterMm2, 0, 1e-9);
  ASSERT_GE(r.planes.size(), 1u);
  EXPECT_LE(r.planes.size(), 2u);
  // The first plane puts the whole underside of the arm above it and the column's foot below.
  const MultidirPlane& p = r.planes.front();
  for (double x : {20.0, 60.0}) {
    for (double y : {0.0, 20.0}) EXPECT_TRUE(above(p, {x, y, 40})) << x << "," << y;
  }
  for (double x : {0.0, 20.0}) {
    for (double y : {0.0, 20.0}) EXPECT_FALSE(above(p, {x, y, 0}));
  }
  EXPECT_GT(p.normal.x(), 0.3);  // printed sideways, towards the arm
  expectValid(l, r, o, "L-bracket");
}

TEST(DecompSynthetic, TBarTwoCutsSeparateBothOverhangs) {
  const Mesh t = makeT();
  MultidirOptions o;
  o.platformMarginMm = 2;
  const MultidirResult r = searchDecomposition(t, o);
  ASSERT_TRUE(r.ok()) << r.message;
  printResult("T beam", r);
  EXPECT_NEAR(r.jgBeforeMm2, 1600, 1e-9);
  EXPECT_NEAR(r.jgAfterMm2, 0, 1e-9);
  ASSERT_EQ(r.planes.size(), 2u);
  // One plane takes the left underside, the other the right one.
  int left = -1, right = -1;
  for (int k = 0; k < 2; ++k) {
    if (above(r.planes[k], {-40, 10, 40}) && above(r.planes[k], {0, 10, 40})) left = k;
    if (above(r.planes[k], {60, 10, 40}) && above(r.planes[k], {20, 10, 40})) right = k;
  }
  EXPECT_GE(left, 0);
  EXPECT_GE(right, 0);
  EXPECT_NE(left, right);
  expectValid(t, r, o, "T");
}

// ---- criteria --------------------------------------------------------------------------------

// Arch + pendant, one candidate normal n = (0, 1, 1)/sqrt(2), alpha_max = 60 deg (so every face
// is safe along n). The pendant hangs from the bridge only: a plane through the pendant or below
// the bridge's bottom leaves the pendant's lower part floating (Criterion II); a plane below
// 0.707 * 11 (footprint y <= 10 plus a 1 mm margin) has the platform above it (Criterion III).
TEST(DecompCriteria, FloatingPieceAndPlatformAboveAreRefused) {
  const Mesh arch = makeArchPendant();
  MultidirOptions o;
  o.alphaMaxDeg = 60;
  o.platformMarginMm = 1;
  o.w = 20;
  const Eigen::Vector3d n = Eigen::Vector3d(0, 1, 1).normalized();
  o.candidateNormals = {n};
  // The evaluation flags the two bad planes.
  const MultidirEvaluation floating = evaluateDecomposition(arch, {{n, 15}}, o);
  ASSERT_TRUE(floating.ok()) << floating.message;
  EXPECT_FALSE(floating.checks[0].connected);
  EXPECT_TRUE(floating.checks[0].platformBelow);
  const MultidirEvaluation platform = evaluateDecomposition(arch, {{n, 5}}, o);
  EXPECT_FALSE(platform.checks[0].platformBelow);
  const MultidirEvaluation fine = evaluateDecomposition(arch, {{n, 31}}, o);
  EXPECT_TRUE(fine.checks[0].connected && fine.checks[0].platformBelow && fine.checks[0].partLargeEnough);
  // The plane removing the most risky area (d ~ 8-17, both undersides) is refused; the search
  // settles for a plane that keeps a sliver of the bridge (d > 40 / sqrt 2), pendant attached.
  for (const char* scheme : {"greedy", "constrained", "beam"}) {
    o.scheme = schemeNamed(scheme);
    const MultidirResult r = searchDecomposition(arch, o);
    ASSERT_TRUE(r.ok()) << r.message;
    ASSERT_FALSE(r.planes.empty()) << scheme;
    EXPECT_GT(r.planes[0].offsetMm, 40 / std::sqrt(2.0)) << scheme;
    EXPECT_GT(r.stats.refusedFloating, 0u) << scheme;
    expectValid(arch, r, o, std::string("arch ") + scheme);
  }
}

TEST(DecompCriteria, TinyPartIsRefused) {
  // A 20 mm cube with a 4 x 4 x 4 nub sticking out sideways at the top (x in [20, 24]), and one
  // candidate normal +X: the platform (footprint + 1 mm) keeps planes at x >= 21, so the only
  // useful part is the nub's outer 3 mm (48 mm^3, < V/10) taking 12 of its 16 mm^2 of underside.
  const Mesh nub = makeBoxUnion({{0, 0, 0, 20, 20, 20}, {20, 8, 16, 24, 12, 20}});
  MultidirOptions o;
  o.platformMarginMm = 1;
  o.candidateNormals = {{1, 0, 0}};
  const MultidirResult refused = searchDecomposition(nub, o);  // w = 10: parts >= V/10
  ASSERT_TRUE(refused.ok());
  EXPECT_NEAR(refused.jgBeforeMm2, 16, 1e-9);
  EXPECT_TRUE(refused.planes.empty());
  EXPECT_NEAR(refused.jgAfterMm2, 16, 1e-9);
  o.w = 1000;
  const MultidirResult allowed = searchDecomposition(nub, o);
  ASSERT_TRUE(allowed.ok());
  ASSERT_EQ(allowed.planes.size(), 1u);
  EXPECT_NEAR(allowed.planes[0].offsetMm, 21, 1e-9);
  EXPECT_NEAR(allowed.jgAfterMm2, 4, 1e-9);
  EXPECT_NEAR(allowed.parts[0].volumeMm3, 48, 5);  // occupancy grid of 0.24 mm cells
  expectValid(nub, allowed, o, "nub");
  // The evaluation flags the same plane as too small at w = 10.
  o.w = 10;
  const MultidirEvaluation e = evaluateDecomposition(nub, allowed.planes, o);
  ASSERT_TRUE(e.ok());
  EXPECT_FALSE(e.checks[0].partLargeEnough);
}

TEST(DecompCriteria, PlatformDiscRadius) {
  // With a disc of radius 200 mm the platform reaches under the whole arm: no sideways plane
  // fits between it and the underside (normals of tilt < 45 deg make the underside risky).
  const Mesh l = makeLBracket(20);
  MultidirOptions o;
  o.platformRadiusMm = 200;
  const MultidirResult r = searchDecomposition(l, o);
  ASSERT_TRUE(r.ok());
  EXPECT_GT(r.jgAfterMm2, 100);
  expectValid(l, r, o, "L disc");
}

// ---- exact J_G -------------------------------------------------------------------------------

TEST(DecompExact, MatchesBruteForceSubdivision) {
  const Mesh l = makeT();
  const std::vector<MultidirPlane> planes = {{Eigen::Vector3d(0.6, 0.1, 0.79).normalized(), 31.3},
                                             {Eigen::Vector3d(-0.7, 0.05, 0.71).normalized(), 17.9},
                                             {Eigen::Vector3d(0.1, -0.3, 0.95).normalized(), 40.2}};
  MultidirOptions o;
  for (size_t count = 0; count <= planes.size(); ++count) {
    const std::vector<MultidirPlane> sub(planes.begin(), planes.begin() + count);
    const MultidirEvaluation e = evaluateDecomposition(l, sub, o);
    ASSERT_TRUE(e.ok());
    const double brute = bruteForceJg(l, sub, 45, 2, 256);
    EXPECT_NEAR(e.jgAfterMm2, brute, 0.01 * brute + 0.5) << count << " planes";
    double sum = 0;
    for (const MultidirPart& p : e.parts) sum += p.riskyAreaMm2;
    EXPECT_NEAR(sum, e.jgAfterMm2, 1e-9);
  }
}

TEST(DecompExact, KittenBeforeAndAfterMatchBruteForce) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const Mesh kitten = test::loadPlaced("pymdp_kitten.off", UpAxis::PosY);
  MultidirOptions o;
  const MultidirEvaluation before = evaluateDecomposition(kitten, {}, o);
  ASSERT_TRUE(before.ok()) << before.message;
  EXPECT_NEAR(before.jgBeforeMm2, 1481.2, 0.5);  // paper Table I: 1481.36
  EXPECT_NEAR(before.jgAfterMm2, before.jgBeforeMm2, 1e-9);
  const MultidirResult r = searchDecomposition(kitten, o);
  ASSERT_TRUE(r.ok()) << r.message;
  const double brute = bruteForceJg(kitten, r.planes, 45, 2, 24);
  std::printf("  Kitten beam: exact J_G %.4f, brute force (24^2 per face) %.4f\n", r.jgAfterMm2, brute);
  EXPECT_NEAR(r.jgAfterMm2, brute, 0.02 * r.jgAfterMm2 + 0.2);
  // Random planes through the model (deterministic), exact vs brute force.
  std::vector<MultidirPlane> random;
  for (int i = 0; i < 4; ++i) {
    const double th = 0.4 + 0.3 * i, ph = 1.1 * i;
    const Eigen::Vector3d n(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
    random.push_back({n, 45.0 + 3.7 * i});
  }
  const MultidirEvaluation e = evaluateDecomposition(kitten, random, o);
  const double bruteRandom = bruteForceJg(kitten, random, 45, 2, 24);
  EXPECT_NEAR(e.jgAfterMm2, bruteRandom, 0.01 * bruteRandom + 0.2);
}

TEST(DecompExact, SearchSumsEqualClippingAndRefinementOnlyLowers) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const Mesh kitten = test::loadPlaced("pymdp_kitten.off", UpAxis::PosY);
  MultidirOptions o;
  o.refine = false;
  const MultidirResult raw = searchDecomposition(kitten, o);
  ASSERT_TRUE(raw.ok()) << raw.message;
  printResult("Kitten beam, no refinement", raw);
  expectValid(kitten, raw, o, "Kitten unrefined");
  o.refine = true;
  const MultidirResult refined = searchDecomposition(kitten, o);
  ASSERT_TRUE(refined.ok());
  printResult("Kitten beam, refined", refined);
  expectValid(kitten, refined, o, "Kitten refined");
  EXPECT_LE(refined.jgAfterMm2, raw.jgAfterMm2 + 1e-9);
  EXPECT_GT(refined.stats.refineEvaluated, 0u);
  EXPECT_LE(refined.jgAfterMm2, 0.81);  // paper Table I: 1481.36 -> 0.81 with 5 parts
}

// ---- schemes and 4dof ------------------------------------------------------------------------

TEST(DecompSchemes, EachSchemeOnTheT) {
  const Mesh t = makeT();
  MultidirOptions o;
  o.platformMarginMm = 2;
  double jg[3];
  int i = 0;
  for (const char* scheme : {"greedy", "constrained", "beam"}) {
    o.scheme = schemeNamed(scheme);
    const MultidirResult r = searchDecomposition(t, o);
    ASSERT_TRUE(r.ok()) << scheme << ": " << r.message;
    printResult(scheme, r);
    EXPECT_LT(r.jgAfterMm2, r.jgBeforeMm2) << scheme;
    EXPECT_GT(r.stats.candidatesEvaluated, 0u);
    expectValid(t, r, o, scheme);
    jg[i++] = r.jgAfterMm2;
  }
  EXPECT_LE(jg[2], std::min(jg[0], jg[1]) + 1e-9);
}

// With alpha_max = 40 deg the L's arm underside is safe only along normals tilted >= 50 deg,
// while a +-Y face turns risky beyond 40 deg of tilt towards -+Y: one plane rotated about y
// (normals in the x-z plane) prints the arm sideways; about x it takes two.
TEST(DecompSchemes, FourDofNormalsAreOnTheStepperGrid) {
  const Mesh l = makeLBracket(20);
  MultidirOptions o;
  o.alphaMaxDeg = 40;
  o.dof = DofMode::FourDof;
  o.rotationAxis = Eigen::Vector3d(0, 2, 0);  // any length
  o.stepAngleDeg = 7.5;
  o.rangeDeg = 60;
  o.platformMarginMm = 2;
  const MultidirResult r = searchDecomposition(l, o);
  ASSERT_TRUE(r.ok()) << r.message;
  printResult("L 4dof about y", r);
  EXPECT_EQ(r.stats.normals, 17u);  // -60 .. 60 in 7.5 deg steps
  EXPECT_NEAR(r.jgAfterMm2, 0, 1e-9);
  ASSERT_FALSE(r.planes.empty());
  const Eigen::Vector3d axis(0, 1, 0), side = axis.cross(Eigen::Vector3d(0, 0, 1));
  for (const MultidirPlane& p : r.planes) {
    EXPECT_NEAR(p.normal.dot(axis), 0, 1e-12);
    EXPECT_NEAR(p.normal.norm(), 1, 1e-12);
    const double theta = std::atan2(p.normal.dot(side), p.normal.z()) * 180 / kPi;
    EXPECT_NEAR(theta / 7.5, std::round(theta / 7.5), 1e-9) << theta;
    EXPECT_LE(std::abs(theta), 60 + 1e-9);
  }
  EXPECT_NEAR(r.rotationAxis.dot(axis), 1, 1e-12);
  expectValid(l, r, o, "L 4dof");
  o.rotationAxis = Eigen::Vector3d(1, 0, 0);
  const MultidirResult across = searchDecomposition(l, o);
  ASSERT_TRUE(across.ok());
  // About x one plane cannot do it: a plane tilted enough (>= 50 deg) to make the underside safe
  // takes the arm's -Y or +Y face above with it. (Two planes tilted both ways can: a V cut.)
  EXPECT_TRUE(across.planes.size() >= 2 || across.jgAfterMm2 > 100) << across.planes.size();
  for (const MultidirPlane& p : across.planes) EXPECT_NEAR(p.normal.x(), 0, 1e-12);
}

TEST(DecompSchemes, FourDofAxisSearchFindsTheBestAxis) {
  const Mesh l = makeLBracket(20);
  MultidirOptions o;
  o.alphaMaxDeg = 40;
  o.dof = DofMode::FourDof;
  o.axisSearch = 12;  // every 15 deg
  o.axisFullSearches = 3;
  o.samples = 72;
  o.platformMarginMm = 2;
  const MultidirResult r = searchDecomposition(l, o);
  ASSERT_TRUE(r.ok()) << r.message;
  printResult("L 4dof, 12 axes", r);
  EXPECT_EQ(r.stats.axesTried, 12u);
  EXPECT_NEAR(r.jgAfterMm2, 0, 1e-9);
  EXPECT_EQ(r.planes.size(), 1u);
  EXPECT_GT(std::abs(r.rotationAxis.y()), std::cos(31 * kPi / 180));  // near y, not x
  EXPECT_NEAR(r.rotationAxis.z(), 0, 1e-12);
  for (const MultidirPlane& p : r.planes) EXPECT_NEAR(p.normal.dot(r.rotationAxis), 0, 1e-12);
  expectValid(l, r, o, "L axis search");
}

// ---- options, statuses, cancellation --------------------------------------------------------

TEST(DecompStatus, BadOptionsAndInputs) {
  const Mesh l = makeLBracket(20);
  auto statusWith = [&](auto edit) {
    MultidirOptions o;
    edit(o);
    return searchDecomposition(l, o).status;
  };
  const double nan = std::nan("");
  EXPECT_EQ(statusWith([](MultidirOptions& o) { o.alphaMaxDeg = 0; }), Status::InvalidOption);
  EXPECT_EQ(statusWith([](MultidirOptions& o) { o.alphaMaxDeg = 90; }), Status::InvalidOption);
  EXPECT_EQ(statusWith([&](MultidirOptions& o) { o.alphaMaxDeg = nan; }), Status::InvalidOption);
  EXPECT_EQ(statusWith([](MultidirOptions& o) { o.beamWidth = 0; }), Status::InvalidOption);
  EXPECT_EQ(statusWith([](MultidirOptions& o) { o.perturbations = -1; }), Status::InvalidOption);
  EXPECT_EQ(statusWith([](MultidirOptions& o) { o.perturbations = 10001; }), Status::InvalidOption);
  EXPECT_EQ(statusWith([](MultidirOptions& o) { o.w = 0.5; }), Status::InvalidOption);
  EXPECT_EQ(statusWith([&](MultidirOptions& o) { o.w = nan; }), Status::InvalidOption);
  EXPECT_EQ(statusWith([&](MultidirOptions& o) { o.delta0 = nan; }), Status::InvalidOption);
  EXPECT_EQ(statusWith([](MultidirOptions& o) { o.relaxFactor = 1; }), Status::InvalidOption);
  EXPECT_EQ(statusWith([](MultidirOptions& o) { o.samples = 0; }), Status::InvalidOption);
  EXPECT_EQ(statusWith([](MultidirOptions& o) { o.offsetStepMm = 0; }), Status::InvalidOption);
  EXPECT_EQ(statusWith([](MultidirOptions& o) { o.offsetStepMm = 1e-4; }), Status::InvalidOption);
  EXPECT_EQ(statusWith([](MultidirOptions& o) { o.axisFullSearches = -1; }), Status::InvalidOption);
  EXPECT_EQ(statusWith([](MultidirOptions& o) { o.floatingToleranceCells = -1; }), Status::InvalidOption);
  EXPECT_EQ(statusWith([](MultidirOptions& o) { o.stepAngleDeg = -1; }), Status::InvalidOption);
  EXPECT_EQ(statusWith([](MultidirOptions& o) { o.rangeDeg = 0; }), Status::InvalidOption);
  EXPECT_EQ(statusWith([](MultidirOptions& o) {
              o.dof = DofMode::FourDof;
              o.rotationAxis = {0, 0, 1};
            }),
            Status::InvalidOption);
  EXPECT_EQ(statusWith([&](MultidirOptions& o) { o.rotationAxis = {nan, 0, 0}; }), Status::InvalidOption);
  EXPECT_EQ(statusWith([](MultidirOptions& o) { o.candidateNormals = {{0, 0, 0}}; }), Status::InvalidOption);
  EXPECT_EQ(statusWith([](MultidirOptions& o) { o.platformMarginMm = -1; }), Status::InvalidOption);
  EXPECT_EQ(statusWith([](MultidirOptions& o) { o.gridResolution = 4; }), Status::InvalidOption);
  EXPECT_EQ(statusWith([](MultidirOptions& o) { o.maxTiltDeg = 0; }), Status::InvalidOption);
  EXPECT_EQ(statusWith([](MultidirOptions& o) { o.similarityFraction = -1; }), Status::InvalidOption);

  EXPECT_EQ(searchDecomposition(Mesh{}).status, Status::EmptyInput);
  Mesh badIndex = l;
  badIndex.triangles[4] = 1000;
  EXPECT_EQ(searchDecomposition(badIndex).status, Status::ParseError);
  Mesh nonFinite = l;
  nonFinite.positions[7] = nan;
  EXPECT_EQ(searchDecomposition(nonFinite).status, Status::NonFiniteVertex);
  // A sheet thinner than half a grid cell holds no cell centre.
  EXPECT_EQ(searchDecomposition(test::makeBox(0, 0, 0, 100, 100, 0.1)).status, Status::DegenerateInput);
  const Mesh sunk = test::makeBox(0, 0, -5, 10, 10, 5);
  EXPECT_EQ(searchDecomposition(sunk).status, Status::InvalidOption);
  EXPECT_EQ(evaluateDecomposition(l, {{Eigen::Vector3d::Zero(), 1}}).status, Status::InvalidOption);
  EXPECT_EQ(evaluateDecomposition(l, {{Eigen::Vector3d(0, 0, 1), nan}}).status, Status::InvalidOption);
}

TEST(DecompStatus, CancellationStopsTheSearch) {
  const Mesh t = makeT();
  int calls = 0;
  const MultidirResult r = searchDecomposition(t, {}, [&](const char* stage, double) {
    EXPECT_STREQ(stage, "decompose");
    return ++calls < 2;
  });
  EXPECT_EQ(r.status, Status::Cancelled);
  EXPECT_TRUE(r.planes.empty());
  bool sawEnd = false;
  const MultidirResult done = searchDecomposition(t, {}, [&](const char*, double f) {
    sawEnd = sawEnd || f == 1.0;
    return true;
  });
  EXPECT_TRUE(done.ok());
  EXPECT_TRUE(sawEnd);
}

// ---- progress per search level ---------------------------------------------------------------

struct LevelReport {
  std::string line;
  int level = 0;
  double jg = 0;
  int beams = 0;
};

// Every progress report of a search: its search levels in order, the fractions in order.
struct Recorded {
  std::vector<LevelReport> levels;
  std::vector<double> fractions;
  bool otherStage = false;
};

ProgressFn recorder(Recorded& rec) {
  return [&rec](const ProgressEvent& e) {
    rec.otherStage = rec.otherStage || std::string(e.stage) != "decompose";
    rec.fractions.push_back(e.fraction);
    if (e.search) rec.levels.push_back({e.search->line, e.search->level, e.search->jgMm2, e.search->beams});
    return true;
  };
}

// The level reports of a finished search against its result: one run per line (levels 0, 1, 2,
// ... from J_G before, nonincreasing, ending with no live beam) in the order `lines`, then the
// chosen sequence, exactly stats.jgPerLevel; the search lines' levels >= 1 number stats.levels;
// the search's own J_G of the returned sequence is one a line reported.
void expectLevels(const Recorded& rec, const MultidirResult& r, const std::vector<std::string>& lines,
                  const std::string& what) {
  EXPECT_FALSE(rec.otherStage) << what;
  for (double f : rec.fractions) {
    EXPECT_GE(f, 0) << what;
    EXPECT_LE(f, 1) << what;
  }
  // The fractions never go back (in 4dof each axis's refinement reports the end of its span).
  for (size_t i = 1; i < rec.fractions.size(); ++i) {
    ASSERT_GE(rec.fractions[i], rec.fractions[i - 1]) << what << ": report " << i;
  }
  if (!rec.fractions.empty()) {
    EXPECT_EQ(rec.fractions.back(), 1.0) << what;
  }
  std::vector<std::vector<LevelReport>> runs;
  for (const LevelReport& l : rec.levels) {
    if (l.level == 0) {
      runs.push_back({l});
      continue;
    }
    ASSERT_FALSE(runs.empty()) << what << ": " << l.line << " level " << l.level << " before any level 0";
    ASSERT_EQ(l.line, runs.back().front().line) << what << ": a line's levels are not contiguous";
    runs.back().push_back(l);
  }
  std::vector<std::string> names;
  for (const auto& run : runs) names.push_back(run.front().line);
  std::vector<std::string> expected = lines;
  expected.push_back("chosen");
  ASSERT_EQ(names, expected) << what;
  size_t searched = 0;
  double least = std::numeric_limits<double>::infinity();
  bool lineEndsAtSearchJg = false;
  for (const auto& run : runs) {
    const std::string& line = run.front().line;
    for (size_t k = 0; k < run.size(); ++k) {
      EXPECT_EQ(run[k].level, static_cast<int>(k)) << what << ": " << line;
      EXPECT_GE(run[k].jg, 0) << what << ": " << line << " level " << k;
    }
    if (line == "chosen") continue;
    searched += run.size() - 1;
    if (line == "screen") continue;  // the coarse model's numbers
    EXPECT_EQ(run.front().jg, r.jgBeforeMm2) << what << ": " << line << " starts at J_G before";
    for (size_t k = 1; k < run.size(); ++k) EXPECT_LE(run[k].jg, run[k - 1].jg) << what << ": " << line << " level " << k;
    EXPECT_EQ(run.back().beams, 0) << what << ": " << line << " ends with live beams";
    least = std::min(least, run.back().jg);
    lineEndsAtSearchJg = lineEndsAtSearchJg || (run.back().jg <= r.stats.searchJgMm2 + 1e-9 &&
                                                r.stats.searchJgMm2 <= run.back().jg + MultidirOptions{}.delta0 + 1e-9);
  }
  EXPECT_EQ(searched, r.stats.levels) << what;
  EXPECT_GE(r.stats.searchJgMm2, least - 1e-9) << what;
  EXPECT_TRUE(lineEndsAtSearchJg) << what << ": no line ended near the search's J_G " << r.stats.searchJgMm2;
  std::vector<double> chosen;
  for (const LevelReport& l : runs.back()) {
    chosen.push_back(l.jg);
    EXPECT_EQ(l.beams, 0) << what;
  }
  EXPECT_EQ(chosen, r.stats.jgPerLevel) << what;
}

// The lines of the 5dof beam scheme: the greedy lines, then one beam line per restart run. The
// restarts stop early only when a line ended at J_G <= delta0 (then so does the result).
std::vector<std::string> beamLines(const MultidirResult& r, const MultidirOptions& o = {}) {
  EXPECT_GE(r.stats.restartsRun, 1u);
  EXPECT_LE(r.stats.restartsRun, static_cast<size_t>(o.restarts));
  if (r.stats.restartsRun < static_cast<size_t>(o.restarts)) {
    EXPECT_LE(r.jgAfterMm2, o.delta0 + 1e-9) << "restarts stopped early";
  }
  std::vector<std::string> lines = {"greedy", "constrained"};
  lines.insert(lines.end(), r.stats.restartsRun, "beam");
  return lines;
}

TEST(DecompProgress, EachSchemeReportsItsLinesLevelByLevelThenTheChosenSequence) {
  const Mesh t = makeT();
  for (const char* scheme : {"greedy", "constrained", "beam"}) {
    MultidirOptions o;
    o.platformMarginMm = 2;
    o.scheme = schemeNamed(scheme);
    Recorded rec;
    const MultidirResult r = searchDecomposition(t, o, recorder(rec));
    ASSERT_TRUE(r.ok()) << r.message;
    ASSERT_FALSE(r.planes.empty()) << scheme;
    const std::vector<std::string> lines =
        std::string(scheme) == "beam" ? beamLines(r, o) : std::vector<std::string>{scheme};
    expectLevels(rec, r, lines, scheme);
  }
  // A box needs no plane: every line stops at level 0, the chosen sequence is the box alone.
  Recorded box;
  const MultidirResult r = searchDecomposition(test::makeBox(0, 0, 0, 20, 20, 20), {}, recorder(box));
  ASSERT_TRUE(r.ok()) << r.message;
  expectLevels(box, r, beamLines(r), "box");
  EXPECT_EQ(r.stats.restartsRun, 1u);  // nothing risky: no second search
  EXPECT_EQ(box.levels.size(), 4u);
  // One restart: the greedy lines and one beam line.
  // The T with parts of at least 95% of its volume (w = 1.05: no cut qualifies): J_G stays above
  // delta0, so every restart runs, each a beam line of its own.
  Recorded all;
  MultidirOptions big;
  big.platformMarginMm = 2;
  big.w = 1.05;
  const MultidirResult rt = searchDecomposition(t, big, recorder(all));
  ASSERT_TRUE(rt.ok()) << rt.message;
  EXPECT_GT(rt.jgAfterMm2, big.delta0);
  EXPECT_EQ(rt.stats.restartsRun, static_cast<size_t>(big.restarts));
  expectLevels(all, rt, {"greedy", "constrained", "beam", "beam", "beam"}, "T, w = 1.05");
}

// 4dof axis search: each screened axis, then the lines of every fully searched axis; the chosen
// sequence once, for the winning axis, after all of them.
TEST(DecompProgress, AxisSearchScreensThenSearchesThenReportsTheWinner) {
  const Mesh l = makeLBracket(20);
  MultidirOptions o;
  o.alphaMaxDeg = 40;
  o.dof = DofMode::FourDof;
  o.axisSearch = 12;
  o.axisFullSearches = 3;
  o.samples = 72;
  o.platformMarginMm = 2;
  Recorded rec;
  const MultidirResult r = searchDecomposition(l, o, recorder(rec));
  ASSERT_TRUE(r.ok()) << r.message;
  std::vector<std::string> lines(12, "screen");
  for (int a = 0; a < 3; ++a) lines.insert(lines.end(), {"greedy", "constrained", "beam"});
  expectLevels(rec, r, lines, "L 4dof, 12 axes");
}

TEST(DecompProgress, CancellingOnASearchLevelStopsTheSearch) {
  const Mesh t = makeT();
  for (const char* at : {"greedy", "beam", "chosen"}) {
    size_t after = 0;
    bool cancelled = false;
    const MultidirResult r = searchDecomposition(t, {}, [&](const ProgressEvent& e) {
      if (cancelled) {
        ++after;
        return false;
      }
      cancelled = e.search && std::string(e.search->line) == at && (e.search->level >= 1 || std::string(at) == "chosen");
      return !cancelled;
    });
    EXPECT_TRUE(cancelled) << at;
    EXPECT_EQ(r.status, Status::Cancelled) << at;
    EXPECT_TRUE(r.planes.empty()) << at;
    EXPECT_EQ(after, 0u) << at << ": reports after the cancel";
  }
}

TEST(DecompProgress, KittenLevelsMatchTheResult) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const Mesh kitten = test::loadPlaced("pymdp_kitten.off", UpAxis::PosY);
  Recorded rec;
  const MultidirResult r = searchDecomposition(kitten, {}, recorder(rec));
  ASSERT_TRUE(r.ok()) << r.message;
  expectLevels(rec, r, beamLines(r), "Kitten");
  // The same search without a callback: the levels cost nothing in the result.
  const MultidirResult quiet = searchDecomposition(kitten);
  ASSERT_TRUE(quiet.ok()) << quiet.message;
  EXPECT_EQ(quiet.jgAfterMm2, r.jgAfterMm2);
  EXPECT_EQ(quiet.stats.jgPerLevel, r.stats.jgPerLevel);
}

// ---- shared closed models --------------------------------------------------------------------

struct SharedModel {
  const char* file;
  UpAxis up;
  double fitMm;  // 0 = as stored (mm)
  double target; // J_G after / before asked for (issue 7)
};

// Up axes checked on the files: Kitten, Yoga, voxelmaam Kitten and platform are Y-up (MANIFEST);
// the bunny head and the bracket have their flat cut / mounting face at min y; Fertility's flat
// base is at min x (normalised file: fitted to 100 mm). Targets of issue 7 (J_G after / before).
const SharedModel kShared[] = {
    {"pymdp_kitten.off", UpAxis::PosY, 0, 0.81 / 1481.2},
    {"voxelmaam_kitten.ply", UpAxis::PosY, 0, 0.1},
    {"compas_bunny_closed_low_res.obj", UpAxis::PosZ, 0, 0.035},
    {"compas_bunny_closed_high_res.stl", UpAxis::PosZ, 0, 0.035},
    {"nestedcages_fertility.off", UpAxis::PosX, 100, 0.36},
    {"compas_branches_70_closed_low_res.stl", UpAxis::PosZ, 0, 0.1},
    {"compas_branches_16_closed_mid_res.stl", UpAxis::PosZ, 0, 0.1},
    {"compas_overhang_coin_closed_low_res.stl", UpAxis::PosZ, 0, 0.1},
    {"voxelmaam_platform.obj", UpAxis::PosY, 0, 0.1},
    {"reinforcedfdm_YogaNew.tet", UpAxis::PosY, 0, 0.1},
    {"reinforcedfdm_bunnyhead.tet", UpAxis::PosY, 0, 0.1},
    {"reinforcedfdm_topopt_new.tet", UpAxis::PosY, 0, 0.1},
};

TEST(DecompShared, BeamBeatsBothGreedySchemesOnEveryClosedModel) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  for (const SharedModel& s : kShared) {
    const Mesh mesh = test::loadPlaced(s.file, s.up, s.fitMm);
    MultidirOptions o;
    double jg[3] = {0, 0, 0};
    int i = 0;
    std::printf("%s (%zu faces)\n", s.file, mesh.faceCount());
    for (const char* scheme : {"greedy", "constrained", "beam"}) {
      o.scheme = schemeNamed(scheme);
      const MultidirResult r = searchDecomposition(mesh, o);
      ASSERT_TRUE(r.ok()) << s.file << " " << scheme << ": " << r.message;
      printResult(scheme, r);
      expectValid(mesh, r, o, std::string(s.file) + " " + scheme);
      jg[i++] = r.jgAfterMm2;
      if (std::string(scheme) == "beam") {
        const double ratio = r.jgBeforeMm2 > 0 ? r.jgAfterMm2 / r.jgBeforeMm2 : 0;
        std::printf("  -> beam ratio %.4f (target %.4f)%s\n", ratio, s.target,
                    ratio <= s.target + 1e-12 ? "" : "  NOT REACHED");
      }
    }
    EXPECT_LE(jg[2], std::min(jg[0], jg[1]) + 1e-6) << s.file;
  }
}

// Restarts: the beam's choices depend on which normals exist, so the same Kitten turned about Z
// decomposes differently. Measured over ten turns (0, 0.5, ..., 3.5, 4, 5 rad): one search gives
// J_G 0.00-4.30 mm^2 (5 of 10 within the paper's 0.81), three restarts 0.00-0.71 (10 of 10; one
// search where the first already ends within delta0). At the two turns below one search reads
// 2.78 and 3.31 mm^2.
TEST(DecompShared, RestartsFindTheKittensDecompositionWhereOneSearchMissesIt) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const Mesh kitten = test::loadPlaced("pymdp_kitten.off", UpAxis::PosY);
  for (const double turn : {0.5, 3.5}) {
    Mesh m = kitten;
    const double c = std::cos(turn), s = std::sin(turn);
    for (size_t i = 0; i < m.vertexCount(); ++i) {
      const double x = m.positions[3 * i], y = m.positions[3 * i + 1];
      m.positions[3 * i] = c * x - s * y;
      m.positions[3 * i + 1] = s * x + c * y;
    }
    // Without the local search moves, which start from each result and so do not nest.
    MultidirOptions one, two, three;
    one.restarts = 1;
    two.restarts = 2;
    one.perturbations = two.perturbations = three.perturbations = 0;
    const MultidirResult r1 = searchDecomposition(m, one);
    const MultidirResult r2 = searchDecomposition(m, two);
    ASSERT_EQ(three.restarts, 3);  // the default
    const MultidirResult r3 = searchDecomposition(m, three);
    ASSERT_TRUE(r1.ok() && r2.ok() && r3.ok()) << r1.message << r2.message << r3.message;
    std::printf("  Kitten turned %.1f rad: J_G one search %.3f, two %.3f, three restarts %.3f mm^2 (%zu parts, %zu run)\n",
                turn, r1.jgAfterMm2, r2.jgAfterMm2, r3.jgAfterMm2, r3.parts.size(), r3.stats.restartsRun);
    // The turns nest (restart j is the same search whatever the count): more restarts never lose.
    EXPECT_LE(r2.jgAfterMm2, r1.jgAfterMm2 + 1e-9) << turn;
    EXPECT_LE(r3.jgAfterMm2, r2.jgAfterMm2 + 1e-9) << turn;
    EXPECT_LE(r3.jgAfterMm2, 0.81) << turn;
    expectValid(m, r3, three, "Kitten turned");
  }
}

// Risky area (along +Z, centroid above the 2 mm band) that no plane with the platform below it
// (Criterion III) can clear, whatever the other criteria: a face can leave the platform part, or
// be safe in another, only in a part whose direction n (tilt <= 90 deg) makes it safe
// (n_f . n + sin alpha >= 0) and whose plane, at or above P(n) = max over the grown footprint of
// n . p, has a corner of the face above it (max_i n . v_i > P(n)). Checked on a grid of
// directions with spacing delta in polar and azimuth angle (every direction lies within delta of
// one), with the Lipschitz margins of both conditions, so the bound is rigorous. Independent of
// the search's code.
double criterionThreeBound(const Mesh& mesh, const MultidirOptions& o, double delta) {
  const double sinAlpha = std::sin(o.alphaMaxDeg * kPi / 180);
  double zmin = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < mesh.vertexCount(); ++i) zmin = std::min(zmin, mesh.vertex(i).z());
  std::vector<Eigen::Vector2d> footprint;
  Eigen::Vector2d c(0, 0);
  for (size_t i = 0; i < mesh.vertexCount(); ++i) {
    if (mesh.vertex(i).z() - zmin <= o.platformBandMm) footprint.emplace_back(mesh.vertex(i).x(), mesh.vertex(i).y());
  }
  for (const auto& q : footprint) c += q;
  c /= static_cast<double>(footprint.size());
  const Eigen::Vector3d c3(c.x(), c.y(), zmin);
  double rv = 0, rp = 0;
  for (size_t i = 0; i < mesh.vertexCount(); ++i) rv = std::max(rv, (mesh.vertex(i) - c3).norm());
  for (const auto& q : footprint) rp = std::max(rp, (q - c).norm());
  const double lipschitz = rv + rp + o.platformMarginMm;
  std::vector<Eigen::Vector3d> dirs;
  std::vector<double> limit;
  for (double th = 0; th <= kPi / 2 + delta / 2; th += delta) {
    for (double ph = 0; ph < 2 * kPi; ph += delta) {
      const double t = std::min(th, kPi / 2);
      const Eigen::Vector3d n(std::sin(t) * std::cos(ph), std::sin(t) * std::sin(ph), std::cos(t));
      double best = -std::numeric_limits<double>::infinity();
      for (const auto& q : footprint) best = std::max(best, n.x() * (q.x() - c.x()) + n.y() * (q.y() - c.y()));
      dirs.push_back(n);
      limit.push_back(best + o.platformMarginMm * std::sin(t));
      if (t == 0) break;  // the pole once
    }
  }
  double bound = 0;
  for (size_t f = 0; f < mesh.faceCount(); ++f) {
    Eigen::Vector3d v[3];
    for (int k = 0; k < 3; ++k) v[k] = mesh.vertex(mesh.triangles[3 * f + k]) - c3;
    Eigen::Vector3d nf = (v[1] - v[0]).cross(v[2] - v[0]);
    const double area = nf.norm() / 2;
    if (!(area > 0)) continue;
    nf.normalize();
    if (!(nf.z() + sinAlpha < 0) || (v[0].z() + v[1].z() + v[2].z()) / 3 < o.platformBandMm) continue;
    bool clearable = false;
    for (size_t j = 0; j < dirs.size() && !clearable; ++j) {
      const double top = std::max({dirs[j].dot(v[0]), dirs[j].dot(v[1]), dirs[j].dot(v[2])});
      clearable = nf.dot(dirs[j]) + sinAlpha >= -delta && top - limit[j] > -lipschitz * delta;
    }
    if (!clearable) bound += area;
  }
  return bound;
}

// The compas bunny stands on a shallow bowl (its closed bottom rises ~10 mm inside a ring): the
// bowl's underside faces down above the platform, and no plane with the platform below it can
// take it off. That bounds J_G after / before from below far above the 0.035 (which
// assumed a flat base like the paper's Bunny). The search never goes below the bound.
TEST(DecompShared, BowlBaseBoundsTheCompasBunnyFromBelow) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const Mesh bunny = test::loadPlaced("compas_bunny_closed_low_res.obj", UpAxis::PosZ);
  const MultidirOptions o;
  const double bound = criterionThreeBound(bunny, o, 0.01);
  const MultidirResult r = searchDecomposition(bunny, o);
  ASSERT_TRUE(r.ok()) << r.message;
  std::printf("  compas bunny: J_G %.1f -> %.1f mm^2 (ratio %.3f); Criterion III bound %.1f (ratio %.3f)\n",
              r.jgBeforeMm2, r.jgAfterMm2, r.jgAfterMm2 / r.jgBeforeMm2, bound, bound / r.jgBeforeMm2);
  EXPECT_GE(r.jgAfterMm2, bound);
  EXPECT_GT(bound, 0.3 * r.jgBeforeMm2);
  // The bound is no artefact of the bunny: the Kitten (flat base) has none.
  EXPECT_EQ(criterionThreeBound(test::loadPlaced("pymdp_kitten.off", UpAxis::PosY), o, 0.02), 0.0);
}

// The iterated local search on the refined planes: it starts from the search's result and keeps a
// move only when the exact J_G drops, so it never loses. The Kitten turned 1 rad about Z ends its
// three restarts at 0.71 mm^2 (measured); the moves take it to 0.00 (4 kept of 47 tried).
TEST(DecompShared, LocalSearchMovesOnlyLowerJG) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  Mesh m = test::loadPlaced("pymdp_kitten.off", UpAxis::PosY);
  const double c = std::cos(1.0), s = std::sin(1.0);
  for (size_t i = 0; i < m.vertexCount(); ++i) {
    const double x = m.positions[3 * i], y = m.positions[3 * i + 1];
    m.positions[3 * i] = c * x - s * y;
    m.positions[3 * i + 1] = s * x + c * y;
  }
  MultidirOptions off;
  off.perturbations = 0;
  const MultidirOptions on;  // the default
  ASSERT_GT(on.perturbations, 0);
  const MultidirResult a = searchDecomposition(m, off);
  const MultidirResult b = searchDecomposition(m, on);
  ASSERT_TRUE(a.ok() && b.ok()) << a.message << b.message;
  std::printf("  Kitten turned 1 rad: J_G without moves %.3f, with %.3f mm^2 (%zu kept of %zu, %.0f ms)\n",
              a.jgAfterMm2, b.jgAfterMm2, b.stats.perturbationsKept, b.stats.perturbations, b.stats.msPerturb);
  EXPECT_EQ(a.stats.perturbations, 0u);
  EXPECT_EQ(a.stats.perturbationsKept, 0u);
  // The same search before the moves.
  EXPECT_EQ(a.stats.searchJgMm2, b.stats.searchJgMm2);
  ASSERT_GT(a.jgAfterMm2, on.delta0) << "the case needs the moves";
  EXPECT_LT(b.jgAfterMm2, a.jgAfterMm2 - 1e-3);
  EXPECT_GE(b.stats.perturbationsKept, 1u);
  EXPECT_LE(b.stats.perturbationsKept, b.stats.perturbations);
  EXPECT_LE(b.stats.perturbations, static_cast<size_t>(on.perturbations));
  expectValid(m, b, on, "Kitten turned, moves");
  // The greedy schemes are the paper's: no moves.
  MultidirOptions greedy;
  greedy.scheme = SearchScheme::Greedy;
  const MultidirResult g = searchDecomposition(m, greedy);
  ASSERT_TRUE(g.ok()) << g.message;
  EXPECT_EQ(g.stats.perturbations, 0u);
}

// The local search reports its progress from 0.9 to 0.99 (the searches before it end at 0.9) and
// stops on a cancel there. The low-resolution compas bunny keeps J_G above delta0, so all the
// moves run.
TEST(DecompShared, LocalSearchReportsProgressAndCancels) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const Mesh bunny = test::loadPlaced("compas_bunny_closed_low_res.obj", UpAxis::PosZ);
  MultidirOptions o;
  o.restarts = 1;
  o.perturbations = 20;
  std::vector<double> fractions;
  const MultidirResult r = searchDecomposition(bunny, o, [&](const char*, double f) {
    fractions.push_back(f);
    return true;
  });
  ASSERT_TRUE(r.ok()) << r.message;
  ASSERT_EQ(r.stats.perturbations, 20u);
  size_t inLocal = 0;
  for (size_t i = 0; i < fractions.size(); ++i) {
    if (i > 0) {
      EXPECT_GE(fractions[i], fractions[i - 1]) << i;
    }
    inLocal += fractions[i] > 0.9 && fractions[i] < 1;
  }
  EXPECT_GE(inLocal, 19u);  // one report per move at least (the first sits at 0.9)
  EXPECT_EQ(fractions.back(), 1.0);
  size_t after = 0;
  bool cancelled = false;
  const MultidirResult c = searchDecomposition(bunny, o, [&](const char*, double f) {
    if (cancelled) {
      ++after;
      return false;
    }
    cancelled = f > 0.95 && f < 1;
    return !cancelled;
  });
  EXPECT_TRUE(cancelled);
  EXPECT_EQ(c.status, Status::Cancelled);
  EXPECT_TRUE(c.planes.empty());
  EXPECT_EQ(after, 0u);
}

// The local search in 4dof: moves turn a plane about the rotary axis, within the range and on the
// stepper's angles. The voxelmaam Kitten about X within +-60 deg (measured): 89.2 -> 88.2 mm^2
// (3 moves kept of 60), on a 2.5 deg stepper 93.05 -> 92.93 (1 kept).
TEST(DecompShared, FourDofLocalSearchStaysOnTheMachinesAngles) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const Mesh kitten = test::loadPlaced("voxelmaam_kitten.ply", UpAxis::PosY);
  for (const double step : {0.0, 2.5}) {
    MultidirOptions on, off;
    on.dof = off.dof = DofMode::FourDof;
    on.rangeDeg = off.rangeDeg = 60;
    on.stepAngleDeg = off.stepAngleDeg = step;
    off.perturbations = 0;
    const MultidirResult a = searchDecomposition(kitten, off);
    const MultidirResult b = searchDecomposition(kitten, on);
    ASSERT_TRUE(a.ok() && b.ok()) << a.message << b.message;
    std::printf("  4dof step %.1f: J_G without moves %.3f, with %.3f mm^2 (%zu kept of %zu)\n", step, a.jgAfterMm2,
                b.jgAfterMm2, b.stats.perturbationsKept, b.stats.perturbations);
    EXPECT_LE(b.jgAfterMm2, a.jgAfterMm2 + 1e-9) << step;
    EXPECT_GE(b.stats.perturbationsKept, 1u) << step;
    EXPECT_LT(b.jgAfterMm2, a.jgAfterMm2 - 1e-3) << step;
    const Eigen::Vector3d side = b.rotationAxis.cross(Eigen::Vector3d(0, 0, 1)).normalized();
    for (const MultidirPlane& p : b.planes) {
      EXPECT_NEAR(p.normal.dot(b.rotationAxis), 0, 1e-12);
      const double deg = std::atan2(p.normal.dot(side), p.normal.z()) * 180 / kPi;
      EXPECT_LE(std::abs(deg), on.rangeDeg + 1e-9);
      if (step > 0) {
        EXPECT_NEAR(deg / step, std::round(deg / step), 1e-6) << deg;
      }
    }
    expectValid(kitten, b, on, "Kitten 4dof moves");
  }
}

TEST(DecompShared, KittenFourDofAxisSearch) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const Mesh kitten = test::loadPlaced("pymdp_kitten.off", UpAxis::PosY);
  MultidirOptions o;
  o.dof = DofMode::FourDof;
  o.axisSearch = 180;
  o.rangeDeg = 60;
  const MultidirResult r = searchDecomposition(kitten, o);
  ASSERT_TRUE(r.ok()) << r.message;
  printResult("Kitten 4dof, 180 axes", r);
  std::printf("  axis (%.3f, %.3f, %.3f)\n", r.rotationAxis.x(), r.rotationAxis.y(), r.rotationAxis.z());
  std::printf("  local search moves: %zu kept of %zu\n", r.stats.perturbationsKept, r.stats.perturbations);
  for (const MultidirPlane& p : r.planes) {
    EXPECT_NEAR(p.normal.dot(r.rotationAxis), 0, 1e-12);
    EXPECT_LE(std::acos(std::min(1.0, p.normal.z())) * 180 / kPi, o.rangeDeg + 1e-9);
  }
  expectValid(kitten, r, o, "Kitten 4dof");
}

}  // namespace
}  // namespace omnislice
