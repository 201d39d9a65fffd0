// SPDX-License-Identifier: MIT
#include "motion/plan_motion.h"

#include <Eigen/Geometry>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>

#include "common/math_constants.h"
#include "kinematics/kinematics.h"
#include "geometry/segment.h"
#include "kinematics/robot_arm.h"
#include "motion/feed_limits.h"
#include "motion/material_height.h"
#include "toolpath/lookahead_time.h"
#include "motion/orientation_smoothing.h"
#include "motion/pose_continuity.h"
#include "motion/track_poses.h"

namespace omnislice {

namespace {

constexpr const char* kStage = "motion";
// At most 2^12 pieces per move: each halving divides the chord error by about 4, so 12 levels
// reduce it by ~10^7; a move that still fails (a branch flip inside it) is left as it is.
constexpr int kMaxChordDepth = 12;

bool isExtruding(MoveKind k) { return k == MoveKind::Print || k == MoveKind::Support; }

std::string fmtVec(const Eigen::Vector3d& v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.4g, %.4g, %.4g)", v.x(), v.y(), v.z());
  return buf;
}

// A target sample: the end of a (possibly subdivided) tool-path move.
struct Piece {
  Eigen::Vector3d pos, axis;
  uint32_t source = 0;
  double filament = 0;
  size_t layer = 0;  // pose-graph layer (shared with the previous piece when it is the same pose)
};


}  // namespace

double fastSingularityMeasure(const Eigen::Matrix<double, 6, 6>& j) {
  // Singular values of J are the square roots of the eigenvalues of J^T J; prod(s) = |det J|.
  const Eigen::Matrix<double, 6, 6> g = j.transpose() * j;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> es(g, Eigen::EigenvaluesOnly);
  const auto& l = es.eigenvalues();  // ascending
  const double smax = std::sqrt(std::max(l(5), 0.0));
  const double smin = std::sqrt(std::max(l(0), 0.0));
  if (!(smax > 0)) return 0;
  return std::sqrt(std::abs(j.determinant())) * std::sqrt(smin / smax);
}

namespace {

// Cholesky factor L of G = J^T J (6 x 6, lower triangle, row-major); false when G is not
// positive definite (J singular to rounding).
bool gramCholesky(const Eigen::Matrix<double, 6, 6>& j, double l[6][6]) {
  double g[6][6];
  for (int a = 0; a < 6; ++a) {
    for (int b = 0; b <= a; ++b) g[a][b] = j.col(a).dot(j.col(b));
  }
  for (int a = 0; a < 6; ++a) {
    for (int b = 0; b <= a; ++b) {
      double v = g[a][b];
      for (int c = 0; c < b; ++c) v -= l[a][c] * l[b][c];
      if (a == b) {
        if (!(v > 0)) return false;
        l[a][a] = std::sqrt(v);
      } else {
        l[a][b] = v / l[b][b];
      }
    }
  }
  return true;
}

// |det J| from the Cholesky factor of J^T J: det(G) = det(J)^2 = prod(diag L)^2.
double absDeterminant(const Eigen::Matrix<double, 6, 6>& j) {
  double l[6][6];
  if (!gramCholesky(j, l)) return std::abs(j.determinant());
  double d = 1;
  for (int a = 0; a < 6; ++a) d *= l[a][a];
  return d;
}

// Lower bound of paper 003's measure w = sqrt(|det J|) sqrt(s6 / s1): s1 <= |J|_F and
// s6 >= 1 / |J^-1|_F give w >= sqrt(|det J| / (|J|_F |J^-1|_F)), within a factor sqrt(6) of w.
// |J^-1|_F^2 = trace(G^-1) = |L^-1|_F^2 (G = J^T J = L L^T), all from one 6 x 6 Cholesky.
double singularityLowerBound(const Eigen::Matrix<double, 6, 6>& j) {
  double l[6][6];
  if (!gramCholesky(j, l)) return 0;
  double det = 1, trG = 0;
  for (int a = 0; a < 6; ++a) {
    det *= l[a][a];
    trG += j.col(a).squaredNorm();
  }
  // Columns of L^-1 by forward substitution; accumulate the squared Frobenius norm.
  double inv2 = 0;
  for (int c = 0; c < 6; ++c) {
    double x[6] = {0, 0, 0, 0, 0, 0};
    for (int a = c; a < 6; ++a) {
      double v = a == c ? 1.0 : 0.0;
      for (int b = c; b < a; ++b) v -= l[a][b] * x[b];
      x[a] = v / l[a][a];
      inv2 += x[a] * x[a];
    }
  }
  if (!(det > 1e-300) || !(inv2 > 0)) return 0;
  return std::sqrt(det / (std::sqrt(trG) * std::sqrt(inv2)));
}

class Planner {
 public:
  Planner(const Toolpath& tp, const MachineProfile& m, const MotionOptions& o, const ProgressFn& p)
      : tp_(tp), m_(m), o_(o), progress_(p) {}

  MachinePath run();

 private:
  bool fail(Status s, const std::string& msg) {
    out_.status = s;
    out_.message = msg;
    return false;
  }
  bool validate();
  void buildPieces();
  bool choose();
  bool chooseTrack(size_t layers);
  bool outOfReach(size_t layer);
  bool emit();
  void finishTimes();

  PoseNodeInfo robotInfo(const MachineValues& q) const;
  double minSingularity(const std::vector<MachineValues>& poses) const;
  bool solveNear(const Eigen::Vector3d& pos, const Eigen::Vector3d& axis, const MachineValues& qa,
                 const MachineValues& qb, const MachineValues& qm, MachineValues& out) const;
  // Split the move qa -> qb until the interpolated tip stays within chordTolerance of the
  // part-frame segment; returns false when some piece could not be brought within it (the two
  // poses are not joined by a continuous motion along the segment, e.g. a branch change).
  bool refine(const MachineValues& qa, const Eigen::Vector3d& pa, const Eigen::Vector3d& ua,
              const MachineValues& qb, const Eigen::Vector3d& pb, const Eigen::Vector3d& ub,
              int depth, std::vector<MachineValues>& values, std::vector<Eigen::Vector3d>& pos);
  // Leave the part along the nozzle axis (G-code kinds: to the safe height), change the pose from
  // `from` to `to` (same tip and axis, another branch or turn), come back; retracting around it.
  void reconfigure(const MachineValues& from, const MachineValues& to, const Eigen::Vector3d& tip,
                   const Eigen::Vector3d& axis, const Move& src, uint32_t source, bool retracted);
  void push(const MachineValues& v, const Move& src, uint32_t source, double filament,
            MoveKind kind);
  // Safe Z of a rotation from `from` to `to` within a part: see planMachineMotion(); NaN when
  // the part's top + safeLift applies.
  double materialSafeZ(const MachineValues& from, const MachineValues& to) const;
  bool rotaryChanges(const MachineValues& a, const MachineValues& b, double degrees) const;

  const Toolpath& tp_;
  const MachineProfile& m_;
  const MotionOptions& o_;
  const ProgressFn& progress_;
  MachinePath out_;
  int n_ = 0;
  bool robot_ = false, gcodeRotary_ = false;
  bool head_ = false;  // head4, head5: the head turns about the carriage point over a fixed bed
  PoseMetric metric_;
  std::vector<std::pair<double, double>> limits_;
  double dhCos_[6] = {1, 1, 1, 1, 1, 1}, dhSin_[6] = {0, 0, 0, 0, 0, 0};  // of the DH twists
  std::vector<Eigen::Vector3d> axes_;
  std::vector<Piece> pieces_;
  std::vector<Eigen::Vector3d> layerPos_, layerAxis_;
  std::vector<size_t> layerPiece_;  // first piece of each layer (SIZE_MAX for the start layer)
  std::vector<MachineValues> layerValues_;
  std::vector<double> speeds_;      // requested speed of every output move
  double safeZ_ = 0;
  std::optional<MaterialHeight> material_;  // G-code rotary kinds without a declared safe Z
  double beadMargin_ = 0;                   // largest half width or height of a printed bead
  double zMax_ = std::numeric_limits<double>::infinity();  // the Z limit
};

bool Planner::validate() {
  n_ = machineAxisCount(m_.kind);
  robot_ = m_.kind == MachineKind::Robot6;
  head_ = m_.kind == MachineKind::Head5 || m_.kind == MachineKind::Head4;
  gcodeRotary_ = m_.kind == MachineKind::Rotary4 || m_.kind == MachineKind::Table5 || head_;
  auto bad = [](double v) { return !std::isfinite(v); };
  if (o_.maxKeptPoses < 0 || o_.trackMaxAlive < 0) {
    return fail(Status::InvalidOption, "maxKeptPoses and trackMaxAlive must be >= 0");
  }
  if (bad(o_.trackSlack) || o_.trackSlack < 0 || bad(o_.trackRestartStep) ||
      o_.trackRestartStep < 0) {
    return fail(Status::InvalidOption, "trackSlack and trackRestartStep must be finite and >= 0");
  }
  if (o_.freeRotationSamples < 1 || o_.freeRotationSamples > 3600) {
    return fail(Status::InvalidOption, "freeRotationSamples must be in [1, 3600]");
  }
  if (bad(o_.maxAxisStepDegrees) || o_.maxAxisStepDegrees < 0.01) {
    return fail(Status::InvalidOption, "maxAxisStepDegrees must be >= 0.01");
  }
  if (bad(o_.filterThresholdDegrees) || o_.filterThresholdDegrees < 0) {
    return fail(Status::InvalidOption, "filterThresholdDegrees must be >= 0");
  }
  if (bad(o_.chordTolerance) || o_.chordTolerance < 1e-6) {
    return fail(Status::InvalidOption, "chordTolerance must be >= 1e-6 mm");
  }
  if (bad(o_.acceleration) || o_.acceleration < 0 || bad(o_.retractSpeed) || o_.retractSpeed <= 0 ||
      bad(o_.safeLift) || o_.safeLift < 0 || bad(o_.rotationThresholdDegrees) ||
      o_.rotationThresholdDegrees < 0 || bad(o_.safeRetract) || o_.safeRetract < 0 ||
      bad(o_.singularityThreshold) || o_.singularityThreshold < 0 ||
      bad(o_.singularityPenalty) || o_.singularityPenalty < 0 || bad(o_.armClearance)) {
    return fail(Status::InvalidOption, "motion options must be finite and non-negative "
                                       "(retractSpeed positive)");
  }
  if (!tp_.start.allFinite()) return fail(Status::InvalidOption, "the start position is not finite");
  axes_.resize(tp_.moves.size());
  for (size_t i = 0; i < tp_.moves.size(); ++i) {
    const Move& mv = tp_.moves[i];
    if (!mv.position.allFinite()) {
      return fail(Status::InvalidOption, "move " + std::to_string(i) + " has a non-finite position");
    }
    const double len = mv.axis.norm();
    if (!mv.axis.allFinite() || !(len > 1e-9)) {
      return fail(Status::InvalidOption, "move " + std::to_string(i) + " at " +
                                             fmtVec(mv.position) +
                                             " has a non-finite or zero-length axis");
    }
    if (!std::isfinite(mv.filament) || !std::isfinite(mv.speed) || mv.speed < 0) {
      return fail(Status::InvalidOption,
                  "move " + std::to_string(i) + " has a non-finite filament or speed");
    }
    axes_[i] = mv.axis / len;
  }
  limits_ = machineLimits(m_);
  for (int i = 0; i < 6; ++i) {
    dhCos_[i] = std::cos(m_.dh[i].alpha);
    dhSin_[i] = std::sin(m_.dh[i].alpha);
  }
  metric_.begin = robot_ ? 0 : 3;
  metric_.end = robot_ ? 6 : n_;
  const double turn = robot_ ? 2 * kPi : 360.0;
  for (int i = metric_.begin; i < metric_.end; ++i) {
    const double span = limits_[i].second - limits_[i].first;
    metric_.period[i] = span >= turn - 1e-9 ? turn : 0.0;
  }
  return true;
}

void Planner::buildPieces() {
  const bool stepped = m_.kind == MachineKind::Rotary4 && m_.stepAngleDegrees > 0;
  // Turns are cut into steps of at most maxAxisStepDegrees whether or not the axes are filtered:
  // the steps make the machine turn the nozzle along the great circle the tool path checked for
  // collisions (curved_toolpath's turn check); without them it interpolates its joints linearly
  // and sweeps the cone elsewhere (a 40 mm yoga, voxel, filter off: about 5,000 colliding samples).
  const bool turns = m_.kind != MachineKind::Cartesian3 && !stepped;
  const bool smooth = o_.smoothOrientations && turns;
  if (smooth) {
    std::vector<int> run(tp_.moves.size(), -1);
    int id = -1;
    for (size_t i = 0; i < tp_.moves.size(); ++i) {
      if (!isExtruding(tp_.moves[i].kind)) continue;
      if (i == 0 || !isExtruding(tp_.moves[i - 1].kind)) ++id;
      run[i] = id;
    }
    out_.stats.filteredOrientations = filterOrientations(axes_, run, o_.filterThresholdDegrees);
  }
  // head4: the nozzle always leans its fixed tilt; only the azimuth (C) of an axis is the
  // machine's to choose. Each axis becomes the head's at its azimuth (a vertical one keeps the
  // previous azimuth: a planar print keeps C still), the azimuths unwrapped along the path, and
  // steps turn C linearly, so every piece is an axis the head can take.
  std::vector<double> azimuth;
  const bool fixedTilt = m_.kind == MachineKind::Head4;
  const double tau = m_.tiltDegrees * kPi / 180.0;
  auto headAxis = [&](double c) {
    return Eigen::Vector3d(std::sin(tau) * std::cos(c), std::sin(tau) * std::sin(c), std::cos(tau));
  };
  if (fixedTilt) {
    azimuth.resize(axes_.size());
    double prev = 0;
    for (size_t i = 0; i < axes_.size(); ++i) {
      const Eigen::Vector3d& u = axes_[i];
      double c = prev;
      if (std::hypot(u.x(), u.y()) > 1e-4) {
        c = std::atan2(u.y(), u.x()) + (tau < 0 ? kPi : 0.0);
        c += 2 * kPi * std::round((prev - c) / (2 * kPi));
      }
      azimuth[i] = prev = c;
      axes_[i] = headAxis(c);
    }
  }
  Eigen::Vector3d prevPos = tp_.start;
  Eigen::Vector3d prevAxis = axes_.empty() ? Eigen::Vector3d::UnitZ() : axes_[0];
  double prevAzimuth = azimuth.empty() ? 0.0 : azimuth[0];
  pieces_.reserve(tp_.moves.size());
  for (size_t i = 0; i < tp_.moves.size(); ++i) {
    const Move& mv = tp_.moves[i];
    size_t sub = 1;
    if (turns && (isExtruding(mv.kind) || robot_)) {
      const double angle = axisAngleDegrees(prevAxis, axes_[i]);
      sub = std::max<size_t>(1, static_cast<size_t>(std::ceil(angle / o_.maxAxisStepDegrees - 1e-9)));
    }
    double given = 0;
    for (size_t k = 1; k <= sub; ++k) {
      const double t = static_cast<double>(k) / static_cast<double>(sub);
      Piece p;
      p.pos = k == sub ? mv.position : Eigen::Vector3d(prevPos + t * (mv.position - prevPos));
      p.axis = k == sub ? axes_[i]
               : fixedTilt ? headAxis(prevAzimuth + t * (azimuth[i] - prevAzimuth))
                           : slerpAxis(prevAxis, axes_[i], t);
      p.source = static_cast<uint32_t>(i);
      // Equal pieces of a straight move have equal lengths: equal shares keep the volume per
      // length; the last share takes the rounding so the sum is exact.
      p.filament = k == sub ? mv.filament - given : mv.filament / static_cast<double>(sub);
      given += p.filament;
      pieces_.push_back(p);
    }
    out_.stats.subdivisions += sub - 1;
    prevPos = mv.position;
    prevAxis = axes_[i];
    if (fixedTilt) prevAzimuth = azimuth[i];
  }
}

PoseNodeInfo Planner::robotInfo(const MachineValues& q) const {
  PoseNodeInfo info;
  // armFrames() with the cosines and sines of the DH twists computed once (the same values).
  std::array<Eigen::Matrix4d, 7> frames;
  frames[0] = Eigen::Matrix4d::Identity();
  for (int i = 0; i < 6; ++i) {
    const DhRow& row = m_.dh[i];
    const double th = q[i] + row.thetaOffset;
    appendDhLink(frames[i], row, std::cos(th), std::sin(th), dhCos_[i], dhSin_[i], frames[i + 1]);
  }
  const Eigen::Vector3d& n = m_.nozzleTip;
  const Eigen::Vector3d u = m_.nozzleAxis.normalized();
  const double height = m_.nozzle.coneLength + m_.nozzle.carriageSize.z();
  const double radius =
      0.5 * std::max(m_.nozzle.carriageSize.x(), m_.nozzle.carriageSize.y()) + o_.armClearance;
  for (int f = 1; f <= 6; ++f) {
    const Eigen::Vector3d p = frames[f].topRightCorner<3, 1>();
    // Environment: the base plane (the table the robot stands on).
    if (p.z() < o_.armClearance - 1e-9 && f > 1) {
      info.feasible = false;
      return info;
    }
    // The extruder (cone and carriage) as a cylinder above the tip along the nozzle axis.
    const double axial = (p - n).dot(u);
    if (axial > 0 && axial < height + o_.armClearance && (p - n - axial * u).norm() < radius) {
      info.feasible = false;
      return info;
    }
  }
  // Penalty below singularityThreshold. Bounds decide most poses without an eigen-solve: with
  // s1 <= |J|_F and s6 >= 1 / |J^-1|_F, w = sqrt(|det J|) sqrt(s6 / s1) is at least
  // sqrt(|det J| / (|J|_F |J^-1|_F)), within a factor sqrt(6) of the truth. The measure itself
  // is computed only when that bound is below the threshold or a tie needs it (measure = NaN).
  if (o_.singularityThreshold > 0 && o_.singularityPenalty > 0) {
    // armJacobian() from the frames already at hand (the same values).
    Eigen::Matrix<double, 6, 6> j;
    const Eigen::Vector3d pe = frames[6].topRightCorner<3, 1>();
    for (int i = 0; i < 6; ++i) {
      const Eigen::Vector3d z = frames[i].block<3, 1>(0, 2);
      const Eigen::Vector3d o = frames[i].topRightCorner<3, 1>();
      j.block<3, 1>(0, i) = z.cross(pe - o) * 1e-3;
      j.block<3, 1>(3, i) = z;
    }
    const double lower = singularityLowerBound(j);
    if (!(lower >= o_.singularityThreshold)) {
      info.measure = fastSingularityMeasure(j);
      if (info.measure < o_.singularityThreshold) {
        info.penalty = o_.singularityPenalty * (1.0 - info.measure / o_.singularityThreshold);
      }
    }
  }
  return info;
}

bool Planner::choose() {
  // Layers: 0 = the start (park) pose, then one per distinct piece pose.
  const Eigen::Vector3d startAxis = pieces_.empty() ? Eigen::Vector3d::UnitZ() : pieces_[0].axis;
  Eigen::Vector3d startPos = tp_.start;
  size_t startPiece = SIZE_MAX;
  {
    IkOptions io;
    io.freeRotationSamples = o_.freeRotationSamples;
    const IkResult r = inverseMap(m_, startPos, startAxis, io);
    // A park position the machine cannot reach: park at the first point instead.
    if (!r.ok() || r.candidates.empty()) {
      if (pieces_.empty()) {
        return fail(Status::InvalidOption, "the start position " + fmtVec(startPos) +
                                               " is out of reach of machine '" + m_.name + "'");
      }
      startPos = pieces_[0].pos;
      startPiece = 0;
    }
  }
  layerPos_.push_back(startPos);
  layerAxis_.push_back(startAxis);
  layerPiece_.push_back(startPiece);
  for (size_t i = 0; i < pieces_.size(); ++i) {
    Piece& p = pieces_[i];
    const bool same = (p.pos - layerPos_.back()).squaredNorm() < 1e-24 &&
                      (p.axis - layerAxis_.back()).squaredNorm() < 1e-24;
    if (!same) {
      layerPos_.push_back(p.pos);
      layerAxis_.push_back(p.axis);
      layerPiece_.push_back(i);
    }
    p.layer = layerPos_.size() - 1;
  }
  const size_t layers = layerPos_.size();
  out_.stats.samples = layers - 1;

  if (robot_ && o_.trackPoses) return chooseTrack(layers);

  std::string ikError;
  IkOptions io;
  io.freeRotationSamples = o_.freeRotationSamples;
  const double total = static_cast<double>(layers);
  const int samples = o_.freeRotationSamples;
  auto candidates = [&](size_t layer, const MachineValues* ref, std::vector<MachineValues>& c,
                        std::vector<int32_t>& keys) {
    if ((layer & 63) == 0 && !reportProgress(progress_, kStage, 0.8 * layer / total)) return false;
    io.reference = ref;
    const IkResult r = inverseMap(m_, layerPos_[layer], layerAxis_[layer], io);
    if (!r.ok()) {
      ikError = r.message;
      return false;
    }
    c.reserve(r.candidates.size());
    for (const IkCandidate& k : r.candidates) {
      c.push_back(k.values);
      if (robot_) {
        // Track key: index of the free-rotation sample (freeAngle = -pi + 2 pi i / samples).
        const long i = std::lround((k.freeAngle + kPi) * samples / (2 * kPi));
        keys.push_back(static_cast<int32_t>(((i % samples + samples) % samples) * 8 + (k.branch & 7)));
      }
    }
    return true;
  };
  auto info = [&](const MachineValues& q) {
    if (robot_) return robotInfo(q);
    return PoseNodeInfo{};
  };
  auto measure = [&](const MachineValues& q) {
    return robot_ ? fastSingularityMeasure(armJacobian(m_.dh, q)) : 0.0;
  };
  PoseChoiceOptions pco;
  pco.maxKept = static_cast<size_t>(o_.maxKeptPoses);
  pco.slack = robot_ ? o_.poseSlack : 0.0;
  PoseChoice pc = choosePoses(layers, metric_, candidates, info, measure, pco);
  if (!ikError.empty()) return fail(Status::InvalidOption, "inverse kinematics: " + ikError);
  if (pc.status == Status::Cancelled) return fail(Status::Cancelled, "cancelled");
  if (!pc.ok()) return outOfReach(pc.failedLayer);
  out_.stats.poseCost = pc.cost;
  out_.stats.greedyPoseCost = pc.greedyCost;
  out_.stats.posePenalty = pc.penalty;
  out_.stats.greedyPosePenalty = pc.greedyPenalty;
  if (robot_) out_.stats.minSingularity = minSingularity(pc.chosen);
  layerValues_ = std::move(pc.chosen);
  unwrapPoses(layerValues_, metric_, limits_);
  return true;
}

double Planner::minSingularity(const std::vector<MachineValues>& poses) const {
  // Weyl: singular values move by at most ||dJ||_2 <= ||dJ||_F, so from the exact s1, s6 of an
  // anchor pose, a pose with Jacobian J has w = sqrt(|det J| s6 / s1) >= sqrt(|det J| (s6a - d) /
  // (s1a + d)), d = ||J - Ja||_F. Only poses whose bound is below the smallest w found so far
  // are solved exactly (and become the anchor): along a smooth path that is a small fraction.
  double mn = std::numeric_limits<double>::infinity();
  const MachineValues* worst = nullptr;
  Eigen::Matrix<double, 6, 6> ja;
  double s1a = 0, s6a = 0;
  bool anchored = false;
  for (const MachineValues& q : poses) {
    const Eigen::Matrix<double, 6, 6> j = armJacobian(m_.dh, q);
    if (anchored) {
      const double d = (j - ja).norm();
      if (s6a > d) {
        const double det = absDeterminant(j);
        const double bound = std::sqrt(det * (s6a - d) / (s1a + d)) * (1 - 1e-9);
        if (bound >= mn) continue;
      }
    }
    const Eigen::Matrix<double, 6, 6> g = j.transpose() * j;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> es(g, Eigen::EigenvaluesOnly);
    s1a = std::sqrt(std::max(es.eigenvalues()(5), 0.0));
    s6a = std::sqrt(std::max(es.eigenvalues()(0), 0.0));
    ja = j;
    anchored = true;
    const double w = s1a > 0 ? std::sqrt(std::abs(j.determinant())) * std::sqrt(s6a / s1a) : 0.0;
    if (w < mn) {
      mn = w;
      worst = &q;
    }
  }
  if (worst) mn = singularityMeasure(armJacobian(m_.dh, *worst));  // the reference SVD value
  return mn;
}

bool Planner::outOfReach(size_t l) {
  if (layerPiece_[l] == SIZE_MAX) {
    return fail(Status::InvalidOption, "the start position " + fmtVec(layerPos_[l]) +
                                           " is out of reach of machine '" + m_.name + "'");
  }
  const Piece& p = pieces_[layerPiece_[l]];
  return fail(Status::InvalidOption, "move " + std::to_string(p.source) + " at " +
                                         fmtVec(p.pos) + " axis " + fmtVec(p.axis) +
                                         " is out of reach of machine '" + m_.name + "'");
}

// Nearest alias of a wrapped joint value inside [lo, hi] (the value itself when inside).
static bool aliasInside(double v, const std::pair<double, double>& l, double& out) {
  constexpr double tol = 1e-9;
  if (v >= l.first - tol && v <= l.second + tol) {
    out = v;
    return true;
  }
  for (int m = 1; m <= 4; ++m) {
    for (const double a : {v + m * 2 * kPi, v - m * 2 * kPi}) {
      if (a >= l.first - tol && a <= l.second + tol) {
        out = a;
        return true;
      }
    }
  }
  return false;
}

bool Planner::chooseTrack(size_t layers) {
  const int samples = o_.freeRotationSamples;
  size_t frameLayer = SIZE_MAX;
  RobotFreeRotation frame;
  const double total = static_cast<double>(layers);
  auto ik = [&](size_t layer, int k, int mask, MachineValues values[8], int branches[8]) {
    if (layer != frameLayer) {
      frame = robotFreeRotation(m_, layerPos_[layer], layerAxis_[layer]);
      frameLayer = layer;
    }
    const Eigen::Matrix4d f = robotFlangeForFreeAngle(frame, robotFreeAngle(k, samples));
    JointValues sol[8];
    int br[8];
    const int n = armInverseBranches(m_.dh, f, mask & m_.ikBranches, sol, br);
    int count = 0;
    for (int i = 0; i < n; ++i) {
      bool ok = true;
      for (int j = 0; j < 6 && ok; ++j) ok = aliasInside(sol[i][j], limits_[j], values[count][j]);
      if (ok) branches[count++] = br[i];
    }
    return count;
  };
  auto info = [&](const MachineValues& q) { return robotInfo(q); };
  auto measure = [&](const MachineValues& q) {
    return fastSingularityMeasure(armJacobian(m_.dh, q));
  };
  const double passes = o_.compareGreedy ? 2.0 : 1.0;  // the greedy pass numbers layers on
  auto layerStart = [&](size_t layer) {
    return (layer & 63) != 0 || reportProgress(progress_, kStage, 0.8 * layer / (passes * total));
  };
  TrackOptions to;
  to.samples = samples;
  to.slack = o_.trackSlack;
  to.restartStep = o_.trackRestartStep;
  to.maxAlive = static_cast<size_t>(o_.trackMaxAlive);
  to.compareGreedy = o_.compareGreedy;
  TrackChoice tc = chooseTrackPoses(layers, metric_, ik, info, measure, to, layerStart);
  if (tc.status == Status::Cancelled) return fail(Status::Cancelled, "cancelled");
  if (tc.status == Status::InvalidOption) return outOfReach(tc.failedLayer);
  if (!tc.ok()) return fail(tc.status, tc.message);
  out_.stats.poseCost = tc.cost;
  out_.stats.posePenalty = tc.penalty;
  out_.stats.greedyPoseCost = tc.greedyCost;
  out_.stats.greedyPosePenalty = tc.greedyPenalty;
  out_.stats.greedyPoseUsed = tc.greedyUsed;
  out_.stats.poseIkCalls = tc.ikCalls;
  out_.stats.poseRestarts = tc.restarts;
  out_.stats.poseAliveNodes = tc.aliveNodes;
  out_.stats.minSingularity = minSingularity(tc.chosen);
  layerValues_ = std::move(tc.chosen);
  unwrapPoses(layerValues_, metric_, limits_);
  return true;
}

bool Planner::rotaryChanges(const MachineValues& a, const MachineValues& b, double degrees) const {
  for (int i = 3; i < n_; ++i) {
    if (std::abs(a[i] - b[i]) > degrees) return true;
  }
  return false;
}

// Machine values for (pos, axis) nearest qm (the linear interpolation of qa and qb).
bool Planner::solveNear(const Eigen::Vector3d& pos, const Eigen::Vector3d& axis,
                        const MachineValues& qa, const MachineValues& qb, const MachineValues& qm,
                        MachineValues& out) const {
  std::vector<MachineValues> cands;
  if (robot_) {
    // The free rotation about the nozzle axis is interpolated too: slerp of the platform
    // rotations of the two ends, corrected by the smallest rotation that aligns the axis.
    const Eigen::Matrix4d wa = robotPlatformPose(m_, qa), wb = robotPlatformPose(m_, qb);
    const Eigen::Quaterniond ra(Eigen::Matrix3d(wa.topLeftCorner<3, 3>()));
    const Eigen::Quaterniond rb(Eigen::Matrix3d(wb.topLeftCorner<3, 3>()));
    Eigen::Matrix3d r = ra.slerp(0.5, rb).toRotationMatrix();
    const Eigen::Vector3d ub = m_.nozzleAxis.normalized();
    r = Eigen::Quaterniond::FromTwoVectors(r * axis, ub).toRotationMatrix() * r;
    Eigen::Matrix4d w = Eigen::Matrix4d::Identity();
    w.topLeftCorner<3, 3>() = r;
    w.topRightCorner<3, 1>() = m_.nozzleTip - r * pos;
    const Eigen::Matrix4d flange = w * m_.flangeToPlatform.inverse();
    JointValues sols[8];
    int branches[8];
    const int count = armInverseBranches(m_.dh, flange, m_.ikBranches, sols, branches);
    for (int i = 0; i < count; ++i) cands.push_back(sols[i]);
  } else {
    IkOptions io;
    io.reference = &qm;
    const IkResult r = inverseMap(m_, pos, axis, io);
    if (!r.ok()) return false;
    for (const IkCandidate& c : r.candidates) cands.push_back(c.values);
  }
  double best = std::numeric_limits<double>::infinity();
  bool found = false;
  for (MachineValues c : cands) {
    // Unwrap next to qm, then require the limits.
    for (int i = metric_.begin; i < metric_.end; ++i) {
      const double p = metric_.period[i];
      if (p <= 0) continue;
      double d = std::fmod(c[i] - qm[i], p);
      if (d > 0.5 * p) d -= p;
      if (d <= -0.5 * p) d += p;
      c[i] = qm[i] + d;
    }
    if (!withinLimits(m_, c, 1e-9)) continue;
    const double d = poseDistance(metric_, c, qm);
    if (d < best) {
      best = d;
      out = c;
      found = true;
    }
  }
  return found;
}

bool Planner::refine(const MachineValues& qa, const Eigen::Vector3d& pa, const Eigen::Vector3d& ua,
                     const MachineValues& qb, const Eigen::Vector3d& pb, const Eigen::Vector3d& ub,
                     int depth, std::vector<MachineValues>& values,
                     std::vector<Eigen::Vector3d>& pos) {
  bool angular = false;
  for (int i = metric_.begin; i < metric_.end; ++i) angular = angular || std::abs(qb[i] - qa[i]) > 1e-12;
  bool exact = true;
  if (angular) {
    MachineValues qm{};
    for (int i = 0; i < 6; ++i) qm[i] = 0.5 * (qa[i] + qb[i]);
    Eigen::Vector3d tip, axis;
    if (forwardMap(m_, qm, tip, axis) && std::sqrt(pointSegmentDistance2(tip, pa, pb)) > o_.chordTolerance) {
      exact = false;
      if (depth < kMaxChordDepth) {
        const Eigen::Vector3d pm = 0.5 * (pa + pb);
        Eigen::Vector3d um = slerpAxis(ua, ub, 0.5);
        MachineValues qs;
        // Tables: keep the rotary values of the joint-space midpoint and move the linear axes so
        // the tip is on the segment, when that midpoint's axis is within 2 degrees of the slerped
        // one. Near the C axis's singularity the slerped axis has an ill-defined azimuth (a C far
        // from both ends), while the joint-space path (B through 0, C turning) is smooth.
        const bool jointMid = !robot_ && axis.dot(um) > std::cos(2.0 * kPi / 180.0) &&
                              solveNear(pm, axis, qa, qb, qm, qs);
        if (jointMid) um = axis;
        if (jointMid || solveNear(pm, um, qa, qb, qm, qs)) {
          const bool left = refine(qa, pa, ua, qs, pm, um, depth + 1, values, pos);
          const bool right = refine(qs, pm, um, qb, pb, ub, depth + 1, values, pos);
          return left && right;
        }
      }
    }
  }
  values.push_back(qb);
  pos.push_back(pb);
  return exact;
}

double Planner::materialSafeZ(const MachineValues& from, const MachineValues& to) const {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (!material_) return nan;
  double turn = 0;
  for (int k = 3; k < n_; ++k) turn = std::max(turn, std::abs(to[k] - from[k]));
  const int steps = std::clamp(static_cast<int>(std::ceil(turn)), 1, 720);
  const double cosMaxTilt = std::cos((90.0 - m_.nozzle.coneHalfAngleDegrees) * kPi / 180.0);
  double top = -std::numeric_limits<double>::infinity();
  MachineValues v = from;
  Eigen::Vector3d tip, axis;
  for (int s = 0; s <= steps; ++s) {
    const double t = double(s) / steps;
    for (int k = 3; k < n_; ++k) v[k] = from[k] + t * (to[k] - from[k]);
    forwardMap(m_, v, tip, axis);
    if (!(axis.z() >= cosMaxTilt)) return nan;
    top = std::max(top, material_->bound(axis.normalized()));
  }
  if (material_->empty()) return -std::numeric_limits<double>::infinity();
  // Between two samples the axis turns at most turn / steps degrees; the support function is
  // radius-Lipschitz in the axis.
  const double slack = material_->radius() * (turn / steps) * kPi / 180.0;
  return m_.pivot.z() + top + slack + beadMargin_ + o_.safeClearance;
}

void Planner::reconfigure(const MachineValues& from, const MachineValues& to,
                          const Eigen::Vector3d& tip, const Eigen::Vector3d& axis, const Move& src,
                          uint32_t source, bool retracted) {
  const bool ownRetract = !retracted && o_.safeRetract > 0;
  if (ownRetract) push(from, src, source, -o_.safeRetract, MoveKind::Retract);
  if (gcodeRotary_) {
    // As a 3+2 safe rotation: lift to the safe height, turn, move over, lower.
    const double local = materialSafeZ(from, to);
    const double zs = std::max({std::isnan(local) ? safeZ_ : std::min(local, zMax_), from[2], to[2]});
    MachineValues a = from;
    a[2] = zs;
    push(a, src, source, 0, MoveKind::Travel);
    for (int k = 3; k < n_; ++k) a[k] = to[k];
    push(a, src, source, 0, MoveKind::Travel);
    a[0] = to[0];
    a[1] = to[1];
    push(a, src, source, 0, MoveKind::Travel);
  } else {
    // Leave along the nozzle axis, change the pose there, come back.
    const Eigen::Vector3d away = tip + std::max(1.0, o_.safeLift) * axis;
    MachineValues la, lb;
    if (solveNear(away, axis, from, from, from, la)) push(la, src, source, 0, MoveKind::Travel);
    if (solveNear(away, axis, to, to, to, lb)) push(lb, src, source, 0, MoveKind::Travel);
  }
  push(to, src, source, 0, MoveKind::Travel);
  if (ownRetract) push(to, src, source, o_.safeRetract, MoveKind::Unretract);
  out_.stats.subdivisions += 3;
  ++out_.stats.safeRotations;
}

void Planner::push(const MachineValues& v, const Move& src, uint32_t source, double filament,
                   MoveKind kind) {
  MachineMove mm;
  mm.values = v;
  mm.filament = filament;
  mm.kind = kind;
  mm.width = src.width;
  mm.height = src.height;
  mm.feature = src.feature;
  mm.part = src.part;
  mm.layer = src.layer;
  mm.source = source;
  forwardMap(m_, v, mm.tip, mm.axis);
  out_.moves.push_back(mm);
  speeds_.push_back(src.speed);
}

bool Planner::emit() {
  out_.start = layerValues_[0];
  if (gcodeRotary_) {
    if (m_.safeZ > 0) {
      safeZ_ = m_.safeZ;
    } else if (head_) {
      // Turning about the carriage point keeps the tip within |tip_offset| of it: the carriage
      // that high above the part's top keeps the tip at least safeLift above the part.
      double top = -std::numeric_limits<double>::infinity();
      for (const Eigen::Vector3d& p : layerPos_) top = std::max(top, p.z());
      safeZ_ = top + m_.tipOffset.norm() + o_.safeLift;
    } else {
      double top = -std::numeric_limits<double>::infinity();
      for (const MachineValues& v : layerValues_) top = std::max(top, v[2]);
      safeZ_ = top + o_.safeLift;
    }
    auto z = m_.axisLimits.find("Z");
    if (z != m_.axisLimits.end()) safeZ_ = std::min(safeZ_, z->second.second);
    // The material's height over the turning platform (motion/material_height): tables only.
    if (!(m_.safeZ > 0) && !head_) material_.emplace(m_.pivot);
    if (z != m_.axisLimits.end()) zMax_ = z->second.second;
  }
  out_.moves.reserve(pieces_.size() + pieces_.size() / 8);
  MachineValues prev = layerValues_[0];
  Eigen::Vector3d prevPos = layerPos_[0], prevAxis = layerAxis_[0];
  bool retracted = false;
  int32_t lastPart = -1;  // part of the last extruding move
  std::vector<MachineValues> vals;
  std::vector<Eigen::Vector3d> poss;
  for (size_t i = 0; i < pieces_.size(); ++i) {
    if ((i & 1023) == 0 &&
        !reportProgress(progress_, kStage, 0.8 + 0.15 * i / static_cast<double>(pieces_.size()))) {
      return fail(Status::Cancelled, "cancelled");
    }
    const Piece& p = pieces_[i];
    const Move& src = tp_.moves[p.source];
    const MachineValues& v = layerValues_[p.layer];
    // Between parts (3+2) every rotation is a safe one, however small (the writers' rule).
    const bool newPart = lastPart >= 0 && src.part != lastPart;
    if (gcodeRotary_ && src.kind == MoveKind::Travel &&
        rotaryChanges(prev, v, newPart ? 1e-6 : o_.rotationThresholdDegrees)) {
      // 3+2 safe rotation: retract, lift, rotate at safe height, move over, lower, unretract.
      const bool ownRetract = !retracted && o_.safeRetract > 0;
      if (ownRetract) push(prev, src, p.source, -o_.safeRetract, MoveKind::Retract);
      const double local = newPart ? std::numeric_limits<double>::quiet_NaN() : materialSafeZ(prev, v);
      const double zs = std::max({std::isnan(local) ? safeZ_ : std::min(local, zMax_), prev[2], v[2]});
      MachineValues a = prev;
      a[2] = zs;
      push(a, src, p.source, 0, MoveKind::Travel);
      for (int k = 3; k < n_; ++k) a[k] = v[k];
      push(a, src, p.source, 0, MoveKind::Travel);
      a[0] = v[0];
      a[1] = v[1];
      push(a, src, p.source, 0, MoveKind::Travel);
      push(v, src, p.source, p.filament, MoveKind::Travel);
      if (ownRetract) push(v, src, p.source, o_.safeRetract, MoveKind::Unretract);
      out_.stats.subdivisions += 3;
      ++out_.stats.safeRotations;
    } else if (p.layer == 0 || (i > 0 && pieces_[i - 1].layer == p.layer)) {
      push(v, src, p.source, p.filament, src.kind);  // same pose: retract, unretract, dwell
    } else {
      vals.clear();
      poss.clear();
      if (!refine(prev, prevPos, prevAxis, v, p.pos, p.axis, 0, vals, poss)) {
        // No continuous motion joins the two poses along the segment (a branch or turn change
        // chosen by the pose continuity): change the pose away from the part at the start, where
        // the pose on v's branch is found, and print the segment from there.
        MachineValues start;
        std::vector<MachineValues> vals2;
        std::vector<Eigen::Vector3d> poss2;
        const bool solved = solveNear(prevPos, prevAxis, v, v, v, start);
        const bool joined = solved && refine(start, prevPos, prevAxis, v, p.pos, p.axis, 0, vals2, poss2);
        if (joined) {
          reconfigure(prev, start, prevPos, prevAxis, src, p.source, retracted);
          vals.swap(vals2);
          poss.swap(poss2);
        }
      }
      // Filament proportional to the part-frame length of each piece (exact sum).
      const double len = (p.pos - prevPos).norm();
      double given = 0;
      Eigen::Vector3d a = prevPos;
      for (size_t k = 0; k < vals.size(); ++k) {
        double f = p.filament - given;
        if (k + 1 < vals.size()) {
          f = len > 0 ? p.filament * (poss[k] - a).norm() / len
                      : p.filament / static_cast<double>(vals.size());
        }
        given += f;
        a = poss[k];
        push(vals[k], src, p.source, f, src.kind);
      }
      out_.stats.subdivisions += vals.size() - 1;
    }
    if (src.kind == MoveKind::Retract) retracted = true;
    if (src.kind == MoveKind::Unretract || isExtruding(src.kind)) retracted = false;
    if (isExtruding(src.kind)) {
      lastPart = src.part;
      // The bead's both ends (the support function of a segment is its ends' largest).
      if (material_ && p.filament > 0) {
        material_->add(prevPos);
        material_->add(p.pos);
        beadMargin_ = std::max({beadMargin_, 0.5 * src.width, src.height});
      }
    }
    prev = v;
    prevPos = p.pos;
    prevAxis = p.axis;
  }
  return true;
}

void Planner::finishTimes() {
  const size_t n = out_.moves.size();
  FeedInput in;
  in.axes = n_;
  in.values.reserve(n + 1);
  in.values.push_back(out_.start);
  in.length.resize(n);
  in.speed.resize(n);
  Eigen::Vector3d tip, axis;
  forwardMap(m_, out_.start, tip, axis);
  for (size_t k = 0; k < n; ++k) {
    const MachineMove& mm = out_.moves[k];
    in.values.push_back(mm.values);
    in.length[k] = (mm.tip - tip).norm();
    in.speed[k] = speeds_[k];
    tip = mm.tip;
  }
  if (robot_) {
    in.dynamics = m_.jointDynamics;
    in.fallbackVelocity.fill(0.5);  // rad/s, only for reorientations with no limit declared
  } else {
    const auto names = machineAxisNames(m_.kind);
    for (int i = 0; i < n_; ++i) {
      auto it = m_.axisDynamics.find(names[i]);
      // G-code firmware plans the junctions and ramps of its linear axes itself (the trapezoid
      // term below estimates them): X Y Z take only their velocity cap here; the finite-difference
      // acceleration and jerk of Eq. 7 at polyline corners would slow every corner of a planar
      // print to a crawl. Rotary axes (A, B, C) keep all three limits (paper 003 Eq. 7-9).
      if (it != m_.axisDynamics.end()) {
        in.dynamics[i] = it->second;
        if (i < 3) in.dynamics[i].acceleration = in.dynamics[i].jerk = 0;
      }
      in.fallbackVelocity[i] = i < 3 ? 50.0 : 90.0;  // mm/s, deg/s
    }
  }
  FeedResult fr = limitFeeds(in);
  double time = 0;
  double maxStep = 0;
  MachineValues prev = out_.start;
  // G-code kinds: the firmware's look-ahead ramps the tip through its junctions (lookahead_time.h)
  // at each move's feed-limited cruise; a move without tip motion is a stop.
  std::vector<PlannedMove> planned(robot_ ? 0 : n);
  Eigen::Vector3d before = Eigen::Vector3d::Zero();  // the tip before move k (the first move's
  forwardMap(m_, out_.start, before, axis);           // direction starts no junction)
  for (size_t k = 0; k < n; ++k) {
    MachineMove& mm = out_.moves[k];
    double t = fr.duration[k];
    const double l = in.length[k];
    if (mm.filament != 0 && !(l > 0)) {
      const double fs = speeds_[k] > 0 ? speeds_[k] : o_.retractSpeed;
      t = std::max(t, std::abs(mm.filament) / fs);
    }
    mm.durationS = t;
    mm.tipSpeed = l > 0 && t > 0 ? l / t : speeds_[k];
    if (!robot_ && l > 0 && t > 0) {
      planned[k] = {(mm.tip - before) / l, l, mm.tipSpeed};
    } else {
      time += t;
    }
    before = mm.tip;
    for (int i = metric_.begin; i < metric_.end; ++i) {
      maxStep = std::max(maxStep, std::abs(mm.values[i] - prev[i]));
    }
    prev = mm.values;
  }
  if (!robot_) time += lookaheadTime(planned, {o_.acceleration, o_.junctionDeviation});
  out_.stats.feedLimitedMoves = fr.limitedMoves;
  out_.stats.estimatedTimeS = time;
  out_.stats.maxJointStep = maxStep;
}

MachinePath Planner::run() {
  out_.machine = m_;
  out_.layerCount = tp_.layerCount;
  if (!validate()) return std::move(out_);
  if (!reportProgress(progress_, kStage, 0)) {
    fail(Status::Cancelled, "cancelled");
    return std::move(out_);
  }
  buildPieces();
  if (!choose()) {
    out_.moves.clear();
    return std::move(out_);
  }
  if (!emit()) {
    out_.moves.clear();
    return std::move(out_);
  }
  finishTimes();
  if (!reportProgress(progress_, kStage, 1)) {
    out_.moves.clear();
    fail(Status::Cancelled, "cancelled");
  }
  return std::move(out_);
}

}  // namespace

MachinePath planMachineMotion(const Toolpath& toolpath, const MachineProfile& machine,
                              const MotionOptions& options, const ProgressFn& progress) {
  Planner planner(toolpath, machine, options, progress);
  return planner.run();
}

}  // namespace omnislice
