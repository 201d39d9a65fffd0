// SPDX-License-Identifier: MIT
// Kinematic-constrained feed rate (paper 003 Section 2.2, Eq. 5-9) and the best drive-plane
// direction by the material deposition rate (Section 2.3, Eq. 10-11, Algorithm 1).
//
// Machine values along a path: the nozzle tip follows the surface with the nozzle axis along the
// surface normal. robot6: the rotation gamma about the nozzle axis is redundant; at each sample it
// is gamma* maximising the singularity parameter w_PS of Eq. 5 over gammaSamples values (Eq. 6;
// w_PS vanishes at singular poses, so "best conditioned" is its maximum, robot_arm.h), refined by
// golden-section search, and the IK branch is the one of largest w_PS within the joint limits
// (ties to rounding, as between mirrored poses, go to the lower branch number). Solved in full at
// one seed sample per cube of gammaSeedSpacing (the sample nearest the cube's centre); every
// other sample starts from its cube's seed (gamma, branch) and refines by one parabolic step
// through gamma and gamma +- pi / gammaSamples (the best of the four values evaluated).
// table5 / rotary4 have no redundancy (their closed-form inverse, kinematics.h): the centre takes
// the first candidate (table5: B >= 0 when within the limits), stencil points the candidate
// nearest the centre's angles, so the stencil stays on one branch and C alias (at a vertical
// axis C is undefined: the centre keeps C = 0 and the stencil's C follows the normal's azimuth,
// a real singularity of the machine that makes f* small there). cartesian3 cannot tilt: its
// nozzle stays vertical and its values are the tip.
//
// Joint velocity, acceleration and jerk along a candidate path (Eq. 7): the machine values are
// computed exactly (inverse kinematics) on a stencil of surface points around each sample (the
// sample's local quadric, normals from it; gamma and branch held at the sample's), a cubic in the
// tangent coordinates (u, v) is fitted to each value, and the path's derivatives follow from the
// cubic along the candidate curve (the drive-plane section: direction f, geodesic curvature from
// the plane): dQ/ds, d2Q/ds2, d3Q/ds3. Eq. 7's differences at chord l_c are these derivatives to
// O(l_c); the stencil radius is l_c. The stencil is the centre, 4 points at l_c / 2 on the
// tangent axes and 8 at l_c every 45 degrees; the cubic's least-squares fit is one 10 x 13
// pseudo-inverse for every sample (errors O(l_c^2) in the second and third derivatives).
// Limitation: a sample carries the surface to second order only, so d2Q/ds2 misses the nozzle
// axis turning from the change of curvature along the path (on the saddle S1 up to ~1e-4 rad/mm^2
// off its centre; with Table 1's limits velocity binds there and f* is unaffected).
// Then (Eq. 8-9) with per-value limits vmax, amax, jmax:
//   f_v = min_j vmax_j / |dQ_j/ds|,  f_a = min_j sqrt(amax_j / |d2Q_j/ds2|),
//   f_j = min_j cbrt(jmax_j / |d3Q_j/ds3|),  f* = min(f_v, f_a, f_j, maxFeed).
// Material deposition rate (Eq. 10): v_e = pi h w_eff f*. Eq. 11: theta* maximises the mean of v_e
// over the samples.
#pragma once
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "common/progress.h"
#include "common/status.h"
#include "isoplanar/effective_width.h"
#include "isoplanar/surface_samples.h"
#include "machine/machine.h"

namespace omnislice {

struct FeedFieldOptions {
  double stencilRadius = 1.0;    // l_c of Eq. 7, mm (> 0)
  int gammaSamples = 36;         // robot6: samples of gamma over [-pi, pi) for Eq. 6 (4..3600)
  double gammaSeedSpacing = 5;   // robot6: Eq. 6 is solved in full at samples about this far
                                 // apart (mm) and refined locally from the nearest seed elsewhere
                                 // (gamma* varies slowly over a layer); 0 = at every sample
  bool useDynamics = true;       // false: every limit infinite (geometry-only tests)
  bool adaptStencil = true;      // table5: the stencil radius shrinks near vertical nozzle axes
                                 // to sin(B) / (20 |kappa|max) (C turns on that scale),
                                 // down to stencilRadius / 16
  bool singleFreeAngle = false;  // robot6: one gamma and branch for every sample (the grid
                                 // value and branch whose smallest w_PS over the seeds is
                                 // largest) instead of gamma* per sample. w_PS is flat over
                                 // gamma (0.1 % over half a radian on the saddle), so gamma* per
                                 // sample wanders and ties between branches flip: the field's
                                 // derivatives hold gamma at the sample's, and a path replayed
                                 // with gamma* per point moves the wrist much faster than they
                                 // say; with one gamma the replay matches the field (tested).
};

// Per-sample kinematic model of a surface on a machine.
struct FeedField : Outcome {
  int axes = 0;                               // machine values used (3..6)
  std::array<AxisDynamics, 6> dynamics{};     // per value, machine units (machine.h)
  std::vector<MachineValues> values;          // per sample: machine values at the sample
  std::vector<uint8_t> reachable;             // per sample: 1 when an inverse within the limits
                                              // exists on the whole stencil
  std::vector<double> freeAngle;              // robot6: gamma* (rad); else 0
  std::vector<double> singularity;            // robot6: w_PS at gamma*; else 0
  // Per sample and value: derivatives of the value over the sample's tangent coordinates
  // (u along tangentU, v along tangentV, mm) from the fitted cubic:
  // [Qu, Qv, Quu, Quv, Qvv, Quuu, Quuv, Quvv, Qvvv].
  std::vector<std::array<std::array<double, 9>, 6>> jets;
  size_t unreachable = 0;                     // samples with reachable = 0
  double ms = 0;
};

// The field for `samples` (surfaceSamples() of a layer) on `machine` (any kind). Progress stage
// "feed". Statuses: InvalidOption (options out of range, unknown kind), Cancelled.
FeedField buildFeedField(const std::vector<SurfaceSample>& samples, const MachineProfile& machine,
                         const FeedFieldOptions& options = {}, const ProgressFn& progress = {});

struct FeedLimit {
  double feed = 0;           // f* (Eq. 9), mm/s; 0 at unreachable samples
  double velocity = 0;       // f_max,v, mm/s (infinity when no value moves / no limit)
  double acceleration = 0;   // f_max,a
  double jerk = 0;           // f_max,j
  int limitingValue = -1;    // index of the value that sets f* (-1: maxFeed or unlimited)
};

// f* at sample i moving along `direction` (part frame; projected onto the tangent plane and
// normalised) on a curve whose geodesic curvature is `geodesicCurvature` (1/mm, positive when the
// curve turns toward normal x direction), capped by maxFeed (mm/s, 0 = none). The curve's third
// order is that of constant geodesic curvature (its projection's x''' = -(kg^2 + kappa^2) t).
// A limit no value reaches is infinity (so is feed when maxFeed = 0 and nothing moves).
FeedLimit feedLimit(const FeedField& field, const SurfaceSample& sample, size_t i,
                    const Eigen::Vector3d& direction, double geodesicCurvature, double maxFeed);

// The same for the section of the surface by the drive plane of angle theta (rad): plane normal
// q = (-sin theta, cos theta, 0), direction f = normalize(n x q) (sign irrelevant: limits are
// symmetric), geodesic curvature of the planar section from the normal curvature along f and q.
FeedLimit driveFeedLimit(const FeedField& field, const SurfaceSample& sample, size_t i,
                         double theta, double maxFeed);

// Derivatives of every machine value over arc length along the drive-plane section of angle theta
// at sample i (the quantities feedLimit() bounds): d1 = dQ/ds, d2 = d2Q/ds2, d3 = d3Q/ds3 in
// machine units per mm^k, for the direction f of driveFrame() (the tests compare them with finite
// differences of exact inverse kinematics).
struct PathDerivatives {
  bool reachable = false;  // false (and zeros) at unreachable samples
  std::array<double, 6> d1{}, d2{}, d3{};
};
PathDerivatives drivePathDerivatives(const FeedField& field, const SurfaceSample& sample, size_t i,
                                     double theta);

// Unit feed direction f and cross direction k (in the tangent plane, k = n x f) of the drive plane
// of angle theta at a sample; false when the plane is tangent to the surface there (|n.q| ~ 1).
bool driveFrame(const SurfaceSample& sample, double theta, Eigen::Vector3d& feed,
                Eigen::Vector3d& cross);

struct DriveDirectionOptions {
  int directions = 180;           // theta samples over [0, pi): theta_i = i pi / directions
  double beadWidth = 0.4;         // s = nozzle diameter, mm
  double maxFeed = 0;             // mm/s cap on f*, 0 = none
  double forcedThetaDegrees = -1; // >= 0: theta* is this (the curve is still computed)
};

struct DriveDirectionResult : Outcome {
  std::vector<double> thetaDegrees;    // the sampled directions
  std::vector<double> depositionRate;  // mean v_e over the samples per direction, mm^3/s (Eq. 11)
  std::vector<double> meanWidth;       // mean w_eff per direction, mm
  std::vector<double> meanFeed;        // mean f* per direction, mm/s
  size_t best = 0;                     // index of the largest depositionRate
  double thetaStarDegrees = 0;         // theta*: thetaDegrees[best], or the forced angle
  double depositionRateAtTheta = 0;    // mean v_e at theta* (at the forced angle when forced)
  size_t samples = 0;                  // samples averaged (unreachable ones count with v_e = 0)
  size_t unreachable = 0;
  double ms = 0;
};

// Algorithm 1: w_eff (table over the samples' curvature and heights) and f* at every sample for
// every direction, v_e by Eq. 10, theta* by Eq. 11. Means are over all samples: unreachable ones
// (and those with height <= 0) count with f* = 0 and v_e = 0, as do samples whose f* is infinite
// (no limit and no maxFeed); meanWidth counts every sample. Progress stage "direction". Statuses:
// InvalidOption (directions < 1, beadWidth <= 0, samples and field of different sizes),
// EmptyInput (no samples), Cancelled.
DriveDirectionResult searchDriveDirection(const std::vector<SurfaceSample>& samples,
                                          const FeedField& field,
                                          const DriveDirectionOptions& options,
                                          const ProgressFn& progress = {});

}  // namespace omnislice
