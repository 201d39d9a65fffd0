// SPDX-License-Identifier: MIT
// Multidir decomposition (paper 000 Sections III-IV), the entry points of decomposition.h: the
// options, the search lines each scheme runs (5dof: restarts on turned spheres of normals; 4dof:
// the axis search, screened by the constrained greedy line), the choice among the lines' refined
// ends, the iterated local search on the winner, and evaluateDecomposition. The parts live in
// decomposition_model.h (faces, occupancy grid, exact J_G), plane_search.h (the beam-guided search
// and its design), candidate_normals.h and plane_refinement.h (local refinement).
#include "common/det_math.h"
#include "common/math_constants.h"
#include "common/stopwatch.h"
#include "multidir/candidate_normals.h"
#include "multidir/decomposition.h"
#include "multidir/decomposition_model.h"
#include "multidir/plane_refinement.h"
#include "multidir/plane_search.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace omnislice {

const char* searchSchemeName(SearchScheme scheme) {
  switch (scheme) {
    case SearchScheme::Greedy: return "greedy";
    case SearchScheme::Constrained: return "constrained";
    case SearchScheme::Beam: return "beam";
  }
  return "beam";
}

const char* dofModeName(DofMode dof) { return dof == DofMode::FourDof ? "4dof" : "5dof"; }
namespace {

using namespace decomposition_detail;

// ---- options ---------------------------------------------------------------------------------

Outcome checkSearchOptions(const MultidirOptions& o, Scheme& scheme, bool& fourDof) {
  Outcome common = checkCommonOptions(o);
  if (!common.ok()) return common;
  auto bad = [](const std::string& what) { return failed<Outcome>(Status::InvalidOption, what); };
  if (o.samples < 1) return bad("samples must be >= 1");
  if (!(o.offsetStepMm > 0) || !std::isfinite(o.offsetStepMm)) return bad("offsetStepMm must be finite and > 0");
  fourDof = o.dof == DofMode::FourDof;
  if (!(o.maxTiltDeg > 0 && o.maxTiltDeg <= 180)) return bad("maxTiltDeg must be in (0, 180]");
  if (!isFinite(o.rotationAxis)) return bad("rotationAxis must be finite");
  if (fourDof && o.axisSearch == 0) {
    const double len = o.rotationAxis.norm();
    if (!(len > 0)) return bad("rotationAxis must not be zero");
    if (std::abs(o.rotationAxis.z()) > 1e-9 * len) return bad("rotationAxis must be horizontal (z = 0)");
  }
  if (o.axisSearch < 0) return bad("axisSearch must be >= 0");
  if (o.axisFullSearches < 0) return bad("axisFullSearches must be >= 0");
  if (!(o.stepAngleDeg >= 0 && o.stepAngleDeg < 180)) return bad("stepAngleDeg must be in [0, 180)");
  if (!(o.rangeDeg > 0 && o.rangeDeg <= 180)) return bad("rangeDeg must be in (0, 180]");
  for (const Vec3& n : o.candidateNormals) {
    if (!isFinite(n) || !(n.norm() > 0)) return bad("candidateNormals must be finite and non-zero");
  }
  if (o.beamWidth < 1) return bad("beamWidth must be >= 1");
  if (o.restarts < 1 || o.restarts > 64) return bad("restarts must be in [1, 64]");
  if (o.perturbations < 0 || o.perturbations > 10000) return bad("perturbations must be in [0, 10000]");
  if (!(o.delta0 > 0) || !std::isfinite(o.delta0)) return bad("delta0 must be finite and > 0");
  if (!(o.relaxFactor > 1) || !std::isfinite(o.relaxFactor)) return bad("relaxFactor must be finite and > 1");
  scheme = o.scheme;
  if (!(o.similarityFraction >= 0) || !std::isfinite(o.similarityFraction)) {
    return bad("similarityFraction must be finite and >= 0");
  }
  if (!(o.similarityAngleDeg >= 0) || !std::isfinite(o.similarityAngleDeg)) {
    return bad("similarityAngleDeg must be finite and >= 0");
  }
  if (!(o.similarityOffsetMm >= 0) || !std::isfinite(o.similarityOffsetMm)) {
    return bad("similarityOffsetMm must be finite and >= 0");
  }
  return {};
}

// ---- the result -----------------------------------------------------------------------------

// The planes, parts (directions, volumes, risky areas), J_G and J_G per level of a sequence.
void fillResult(const Model& m, const std::vector<Vec3>& bestN, const std::vector<double>& bestD,
                MultidirResult& result) {
  const auto t0 = Clock::now();
  result.planes.clear();
  result.parts.clear();
  result.stats.jgPerLevel.clear();
  const double cellVolume = m.h * m.h * m.h;
  size_t count = 0;
  Bits kept = cellsKept(m, bestN, bestD, 0, count);
  for (size_t k = 0; k < bestN.size(); ++k) {
    result.planes.push_back({bestN[k], bestD[k]});
    Bits below(kept.size(), 0);
    size_t nBelow = 0;
    forEachBit(kept, [&](size_t c) {
      if (bestN[k].dot(m.centre[c]) <= bestD[k]) {
        setBit(below, c);
        ++nBelow;
      }
    });
    MultidirPart part;
    part.direction = bestN[k];
    part.plane = static_cast<int>(k);
    part.volumeMm3 = (count - nBelow) * cellVolume;
    result.parts.push_back(part);
    kept.swap(below);
    count = nBelow;
  }
  MultidirPart base;
  base.volumeMm3 = count * cellVolume;
  result.parts.push_back(base);
  const std::vector<double> risk = exactRisk(m, bestN, bestD);
  result.jgAfterMm2 = 0;
  for (size_t k = 0; k < risk.size(); ++k) {
    result.parts[k].riskyAreaMm2 = risk[k];
    result.jgAfterMm2 += risk[k];
  }
  for (size_t k = 0; k <= bestN.size(); ++k) {
    const std::vector<Vec3> pn(bestN.begin(), bestN.begin() + k);
    const std::vector<double> pd(bestD.begin(), bestD.begin() + k);
    double jg = 0;
    for (double r : exactRisk(m, pn, pd)) jg += r;
    result.stats.jgPerLevel.push_back(jg);
  }
  result.stats.msExact += msSince(t0);
}

// Fills planes/parts/numbers of `result` from the line ends of finished searches, each refined
// when asked; the least exact J_G wins (then fewer planes, then the first). The refinement
// reports progress at `fraction` (the end of these searches' span).
bool collect(const Model& m, const MultidirOptions& o, bool fourDof, const Vec3& axis,
             std::vector<LineEnd> ends, bool perturb, const ProgressFn& progress, double fraction,
             MultidirResult& result) {
  std::vector<Vec3> bestN;
  std::vector<double> bestD;
  double bestJ = std::numeric_limits<double>::infinity();
  // Lines that ended on the same planes (often greedy and constrained) are refined once.
  std::vector<uint8_t> repeated(ends.size(), 0);
  for (size_t i = 0; i < ends.size(); ++i) {
    for (size_t q = 0; q < i && !repeated[i]; ++q) {
      repeated[i] = ends[q].ns == ends[i].ns && ends[q].ds == ends[i].ds;
    }
  }
  for (size_t i = 0; i < ends.size(); ++i) {
    if (repeated[i]) continue;
    LineEnd& e = ends[i];
    std::vector<Vec3>& ns = e.ns;
    std::vector<double>& ds = e.ds;
    if (o.refine && !ns.empty()) {
      const auto t0 = Clock::now();
      bool cancelled = false;
      result.stats.refineEvaluated += refinePlanes(m, o, fourDof, axis, ns, ds, progress, fraction, cancelled);
      result.stats.msRefine += msSince(t0);
      if (cancelled) return false;
    }
    const auto t0 = Clock::now();
    double jg = 0;
    for (double r : exactRisk(m, ns, ds)) jg += r;
    result.stats.msExact += msSince(t0);
    if (jg < bestJ - 1e-9 || (jg <= bestJ + 1e-9 && ns.size() < bestN.size())) {
      bestJ = jg;
      bestN = ns;
      bestD = ds;
      result.stats.searchJgMm2 = e.searchJg;
    }
  }
  if (perturb) {
    const auto t0 = Clock::now();
    bool cancelled = false;
    result.stats.perturbationsKept +=
        perturbPlanes(m, o, fourDof, axis, bestN, bestD, bestJ, progress, fraction, 0.99, cancelled, result.stats);
    result.stats.msPerturb += msSince(t0);
    if (cancelled) return false;
  }
  fillResult(m, bestN, bestD, result);
  return true;
}

// The Cancelled result: the numbers known before the search and the statistics so far.
MultidirResult cancelledResult(const Model& m, const MultidirStats& stats) {
  MultidirResult c;
  c.status = Status::Cancelled;
  c.message = "decomposition cancelled";
  c.jgBeforeMm2 = m.jgBefore;
  c.volumeMm3 = m.volume;
  c.stats = stats;
  return c;
}

// `result` carrying another step's failure.
MultidirResult withFailure(MultidirResult result, const Outcome& failure) {
  result.status = failure.status;
  result.message = failure.message;
  return result;
}

// ---- the lines of each scheme ------------------------------------------------------------------

// The lines of `scheme` from the search's root, within the progress span [base, base + span).
// The beam scheme also runs the greedy and constrained-greedy lines from the same root (two
// extra beams of width 1): the best J_G over all of them wins, so the beam never does worse.
// False when cancelled.
bool runScheme(Search& search, Scheme scheme, const MultidirOptions& options, double base, double span) {
  if (scheme != Scheme::Beam) {
    return search.runLine(scheme, 1, base, span, scheme == Scheme::Greedy ? "greedy" : "constrained");
  }
  return search.runLine(Scheme::Greedy, 1, base, 0.1 * span, "greedy") &&
         search.runLine(Scheme::Constrained, 1, base + 0.1 * span, 0.1 * span, "constrained") &&
         search.runLine(Scheme::Beam, static_cast<size_t>(options.beamWidth), base + 0.2 * span,
                        0.8 * span, "beam");
}

// 5dof. Restart j samples the sphere turned about Z by 2 pi frac(j (sqrt 2 - 1)): the beam's
// choices depend on which normals exist, so each restart explores other decompositions, and as the
// turns never repeat, more restarts only add searches. The first runs the scheme (with the
// greedy lines), the others the beam line only. They stop once a line ends at J_G <= delta0
// (the search's own tolerance for "no risky area": refinement only lowers it). The lines' ends
// are then collected into `result` (searches within progress [0, searchEnd)). False when
// cancelled.
bool searchFiveDof(const Model& m, const MultidirOptions& options, Scheme scheme, bool perturb, double searchEnd,
                   const ProgressFn& progress, MultidirResult& result) {
  std::vector<LineEnd> ends;
  const int restarts = scheme == Scheme::Beam && options.candidateNormals.empty() ? options.restarts : 1;
  const double turn = std::sqrt(2.0) - 1;
  for (int j = 0; j < restarts; ++j) {
    Search search(m, options, result.stats, progress);
    const double phase = 2 * kPi * (j * turn - std::floor(j * turn));
    const std::vector<Vec3> normals = sphereNormals(options, phase);
    result.stats.normals = normals.size();
    search.setNormals(normals);
    const double base = searchEnd * j / restarts, span = searchEnd / restarts;
    const bool ran = j == 0 ? runScheme(search, scheme, options, base, span)
                            : search.runLine(Scheme::Beam, static_cast<size_t>(options.beamWidth), base, span, "beam");
    if (!ran) return false;
    lineEnds(search, ends);
    ++result.stats.restartsRun;
    double least = std::numeric_limits<double>::infinity();
    for (const LineEnd& e : ends) least = std::min(least, e.searchJg);
    if (least <= options.delta0) break;
  }
  return collect(m, options, false, Vec3::Zero(), std::move(ends), perturb, progress, searchEnd, result);
}

// 4dof: the rotary axes to try, axisSearch horizontal ones at 180/axisSearch degree spacing, or
// rotationAxis alone.
std::vector<Vec3> rotaryAxes(const MultidirOptions& options) {
  std::vector<Vec3> axes;
  if (options.axisSearch > 0) {
    for (int i = 0; i < options.axisSearch; ++i) {
      const double phi = kPi * i / options.axisSearch;
      axes.emplace_back(det::cos(phi), det::sin(phi), 0);
    }
  } else {
    axes.push_back(options.rotationAxis.normalized());
  }
  return axes;
}

// The screening only ranks the axes: the constrained greedy line on half the grid resolution
// and, without a stepper, half the normals on each circle.
MultidirOptions screeningOptions(const MultidirOptions& options) {
  MultidirOptions coarse = options;
  coarse.gridResolution = std::max(16, options.gridResolution / 2);
  if (coarse.stepAngleDeg == 0) coarse.samples = std::max(1, options.samples / 2);
  return coarse;
}

// The constrained greedy line on every axis of the coarse model `mc` (progress [0, screenSpan)),
// ranked by J_G + 1e-9 per plane, then (exact ties, e.g. two axes that both reach J_G 0 with one
// plane) the larger model left on the platform; returns the axes' indices to search fully: the
// axisFullSearches best, at least 3 degrees apart (neighbours rank alike), then the next best.
// False when cancelled.
bool screenAxes(const Model& mc, const MultidirOptions& coarse, const std::vector<Vec3>& axes,
                size_t axisFullSearches, double screenSpan, const ProgressFn& progress, MultidirStats& stats,
                std::vector<size_t>& full) {
  std::vector<std::tuple<double, size_t, size_t>> rank;
  for (size_t a = 0; a < axes.size(); ++a) {
    Search search(mc, coarse, stats, progress);
    search.setNormals(circleNormals(coarse, axes[a]));
    const double span = screenSpan / axes.size();
    if (!search.runLine(Scheme::Constrained, 1, a * span, span, "screen")) return false;
    const Node& b = search.node(search.best());
    rank.emplace_back(b.jg + 1e-9 * b.level, mc.cells - b.cellCount, a);
  }
  std::stable_sort(rank.begin(), rank.end());
  full.clear();
  for (int pass = 0; pass < 2 && full.size() < axisFullSearches; ++pass) {
    for (const auto& r : rank) {
      if (full.size() >= axisFullSearches) break;
      bool near = false;
      for (size_t f : full) {
        const double cosAngle = std::abs(axes[f].dot(axes[std::get<2>(r)]));
        near = near || f == std::get<2>(r) || (pass == 0 && cosAngle > det::cos(3 * kPi / 180));
      }
      if (!near) full.push_back(std::get<2>(r));
    }
  }
  return true;
}

// The scheme on each axis of `full` (progress from screenSpan on), every line's end refined; the
// least exact J_G wins (then fewer planes, then the first axis): its planes, parts, J_G and axis
// go into `result`. False when cancelled.
bool searchAxes(const Model& m, const MultidirOptions& options, Scheme scheme, const std::vector<Vec3>& axes,
                const std::vector<size_t>& full, double screenSpan, bool perturb, double searchEnd,
                const ProgressFn& progress, MultidirResult& result) {
  bool have = false;
  for (size_t i = 0; i < full.size(); ++i) {
    const size_t a = full[i];
    Search search(m, options, result.stats, progress);
    const std::vector<Vec3> normals = circleNormals(options, axes[a]);
    result.stats.normals = normals.size();
    search.setNormals(normals);
    const double span = ((perturb ? searchEnd : 1.0) - screenSpan) / full.size();
    if (!runScheme(search, scheme, options, screenSpan + i * span, span)) return false;
    MultidirResult trial;
    std::vector<LineEnd> ends;
    lineEnds(search, ends);
    if (!collect(m, options, true, axes[a], std::move(ends), false, progress,
                 std::min(0.99, screenSpan + (i + 1) * span), trial)) {
      return false;
    }
    result.stats.msExact += trial.stats.msExact;
    result.stats.msRefine += trial.stats.msRefine;
    result.stats.refineEvaluated += trial.stats.refineEvaluated;
    const bool better = !have || trial.jgAfterMm2 < result.jgAfterMm2 - 1e-9 ||
                        (trial.jgAfterMm2 <= result.jgAfterMm2 + 1e-9 &&
                         trial.planes.size() < result.planes.size());
    if (better) {
      have = true;
      result.planes = trial.planes;
      result.parts = trial.parts;
      result.jgAfterMm2 = trial.jgAfterMm2;
      result.rotationAxis = axes[a];
      result.stats.jgPerLevel = trial.stats.jgPerLevel;
      result.stats.searchJgMm2 = trial.stats.searchJgMm2;
    }
  }
  return true;
}

// The iterated local search (beam scheme) once, on the chosen axis (progress 0.9 to 0.99).
// False when cancelled.
bool perturbOnChosenAxis(const Model& m, const MultidirOptions& options, const ProgressFn& progress,
                         MultidirResult& result) {
  std::vector<Vec3> ns;
  std::vector<double> ds;
  for (const MultidirPlane& p : result.planes) {
    ns.push_back(p.normal);
    ds.push_back(p.offsetMm);
  }
  double jg = result.jgAfterMm2;
  const auto tp = Clock::now();
  bool stopped = false;
  const size_t kept =
      perturbPlanes(m, options, true, result.rotationAxis, ns, ds, jg, progress, 0.9, 0.99, stopped, result.stats);
  result.stats.msPerturb += msSince(tp);
  if (stopped) return false;
  if (kept > 0) {
    result.stats.perturbationsKept += kept;
    fillResult(m, ns, ds, result);
  }
  return true;
}

// 4dof: the axes (screened by the constrained greedy line with the beam scheme, when there are
// more than axisFullSearches), the scheme on the best of them, the local search on the winner.
// Statuses: those of the coarse model's buildModel, Cancelled.
Outcome searchFourDof(const Mesh& mesh, const Model& m, const MultidirOptions& options, Scheme scheme,
                      bool perturb, double searchEnd, const ProgressFn& progress, MultidirResult& result) {
  const std::vector<Vec3> axes = rotaryAxes(options);
  // Axis search with the beam: every axis is screened by the constrained greedy line, the beam
  // runs on the axisFullSearches best of them (all when 0).
  std::vector<size_t> full(axes.size());
  std::iota(full.begin(), full.end(), 0);
  const bool screen = scheme == Scheme::Beam && options.axisFullSearches > 0 &&
                      axes.size() > static_cast<size_t>(options.axisFullSearches);
  const double screenSpan = screen ? 0.5 : 0.0;
  if (screen) {
    const MultidirOptions coarse = screeningOptions(options);
    Model mc;
    const auto tc = Clock::now();
    const Outcome ok = buildModel(mesh, coarse, mc);
    result.stats.msPrepare += msSince(tc);
    if (!ok.ok()) return ok;
    if (!screenAxes(mc, coarse, axes, static_cast<size_t>(options.axisFullSearches), screenSpan, progress,
                    result.stats, full)) {
      return failed<Outcome>(Status::Cancelled, "decomposition cancelled");
    }
  }
  if (!searchAxes(m, options, scheme, axes, full, screenSpan, perturb, searchEnd, progress, result)) {
    return failed<Outcome>(Status::Cancelled, "decomposition cancelled");
  }
  result.stats.axesTried = axes.size();
  if (perturb && !perturbOnChosenAxis(m, options, progress, result)) {
    return failed<Outcome>(Status::Cancelled, "decomposition cancelled");
  }
  return {};
}

// The returned sequence level by level ("chosen" levels, once the search and in 4dof the axis
// are decided), then the end of the stage. False when cancelled.
bool reportChosenLevels(const MultidirStats& stats, const ProgressFn& progress) {
  for (size_t k = 0; k < stats.jgPerLevel.size(); ++k) {
    const SearchLevelProgress s{"chosen", static_cast<int>(k), stats.jgPerLevel[k], 0};
    if (!reportProgress(progress, "decompose", 1.0, s)) return false;
  }
  reportProgress(progress, "decompose", 1.0);
  return true;
}

}  // namespace

MultidirResult searchDecomposition(const Mesh& mesh, const MultidirOptions& options,
                                   const ProgressFn& progress) {
  const auto tStart = Clock::now();
  MultidirResult result;
  Scheme scheme = Scheme::Beam;
  bool fourDof = false;
  Outcome ok = checkSearchOptions(options, scheme, fourDof);
  if (ok.ok()) ok = checkMesh(mesh);
  if (!ok.ok()) return withFailure(std::move(result), ok);
  Model m;
  auto t0 = Clock::now();
  ok = buildModel(mesh, options, m);
  result.stats.msPrepare = msSince(t0);
  if (!ok.ok()) return withFailure(std::move(result), ok);
  // Each state holds two arrays of (extent / step) offsets per normal: refuse absurd steps.
  if ((m.hi - m.lo).norm() / options.offsetStepMm > 20000) {
    result.status = Status::InvalidOption;
    result.message = "offsetStepMm is too small for the model (over 20000 offsets per normal)";
    return result;
  }
  result.jgBeforeMm2 = m.jgBefore;
  result.volumeMm3 = m.volume;
  result.stats.gridCells = m.cells;
  result.stats.cellMm = m.h;
  result.stats.orphanCells = m.orphans;
  // The beam's best sequence then goes through the iterated local search (the last 9% of the
  // progress).
  const bool perturb = scheme == Scheme::Beam && options.refine && options.perturbations > 0;
  const double searchEnd = perturb ? 0.9 : 0.99;
  if (!fourDof) {
    if (!searchFiveDof(m, options, scheme, perturb, searchEnd, progress, result)) {
      return cancelledResult(m, result.stats);
    }
  } else {
    ok = searchFourDof(mesh, m, options, scheme, perturb, searchEnd, progress, result);
    if (ok.status == Status::Cancelled) return cancelledResult(m, result.stats);
    if (!ok.ok()) return withFailure(std::move(result), ok);
  }
  result.stats.msTotal = msSince(tStart);
  if (!reportChosenLevels(result.stats, progress)) return cancelledResult(m, result.stats);
  return result;
}

MultidirEvaluation evaluateDecomposition(const Mesh& mesh, const std::vector<MultidirPlane>& planes,
                                         const MultidirOptions& options) {
  MultidirEvaluation result;
  Outcome ok = checkCommonOptions(options);
  for (const MultidirPlane& p : planes) {
    if (!ok.ok()) break;
    if (!isFinite(p.normal) || !(p.normal.norm() > 0) || !std::isfinite(p.offsetMm)) {
      ok = failed<Outcome>(Status::InvalidOption, "a plane has a zero or non-finite normal or offset");
    }
  }
  if (ok.ok()) ok = checkMesh(mesh);
  Model m;
  if (ok.ok()) ok = buildModel(mesh, options, m);
  if (!ok.ok()) {
    result.status = ok.status;
    result.message = ok.message;
    return result;
  }
  std::vector<Vec3> ns;
  std::vector<double> ds;
  for (const MultidirPlane& p : planes) {
    const double len = p.normal.norm();
    ns.push_back(p.normal / len);
    ds.push_back(p.offsetMm / len);
  }
  const std::vector<double> risk = exactRisk(m, ns, ds);
  result.jgBeforeMm2 = m.jgBefore;
  const double cellVolume = m.h * m.h * m.h;
  Bits s((m.cells + 63) / 64, 0);
  for (size_t c = 0; c < m.cells; ++c) setBit(s, c);
  size_t count = m.cells;
  FloodScratch fs;
  for (size_t k = 0; k < ns.size(); ++k) {
    MultidirPlaneCheck check;
    size_t nBelow = 0;
    Bits below = cellsBelow(m, s, ns[k], ds[k], nBelow);
    const size_t nAbove = count - nBelow;
    check.partVolumeMm3 = nAbove * cellVolume;
    check.partLargeEnough = nAbove > 0 && nAbove * options.w >= static_cast<double>(m.cells) - 1e-9;
    check.platformBelow = m.platformLimit(ns[k]) <= ds[k] + 1e-9;
    const size_t reached = reachableBelow(m, s, ns[k], ds[k], fs);
    check.connected = static_cast<double>(nBelow - reached) <= options.floatingToleranceCells;
    check.floatingVolumeMm3 = (nBelow - reached) * cellVolume;
    result.checks.push_back(check);
    MultidirPart part;
    part.direction = ns[k];
    part.plane = static_cast<int>(k);
    part.volumeMm3 = check.partVolumeMm3;
    part.riskyAreaMm2 = risk[k];
    result.parts.push_back(part);
    s.swap(below);
    count = nBelow;
  }
  MultidirPart base;
  base.volumeMm3 = count * cellVolume;
  base.riskyAreaMm2 = risk.back();
  result.parts.push_back(base);
  for (double r : risk) result.jgAfterMm2 += r;
  return result;
}

}  // namespace omnislice
