// SPDX-License-Identifier: MIT
#include "common/stopwatch.h"
#include "pipeline/isoplanar_fill.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "isoplanar/effective_width.h"
#include "isoplanar/feed_rate.h"
#include "isoplanar/isoplanar_paths.h"
#include "isoplanar/surface_samples.h"
#include "common/stopwatch.h"

namespace omnislice {

namespace {


IsoplanarFillResult fail(const Outcome& o) { return failed<IsoplanarFillResult>(o); }

// f* on a mesh edge: the two vertices' limits blended linearly (0 where either is unreachable).
FeedFn edgeFeed(const FeedField& field, const std::vector<SurfaceSample>& samples, double maxFeed) {
  return [&field, &samples, maxFeed](uint32_t a, uint32_t b, double t, const Eigen::Vector3d& dir,
                                     double kg) {
    const double fa = feedLimit(field, samples[a], a, dir, kg, maxFeed).feed;
    if (a == b || t <= 0) return fa;
    const double fb = feedLimit(field, samples[b], b, dir, kg, maxFeed).feed;
    if (fa <= 0 || fb <= 0) return 0.0;
    return (1 - t) * fa + t * fb;
  };
}

}  // namespace

IsoplanarFillResult planIsoplanarFill(const Mesh& surface, const MachineProfile& machine,
                                      const IsoplanarSettings& settings,
                                      const IsoplanarFillOptions& options,
                                      const ProgressFn& progress) {
  IsoplanarFillResult out;
  Clock::time_point t0 = Clock::now();
  SurfaceSamplesResult samples = surfaceSamples(surface, options.layerHeight);
  if (!samples.ok()) return fail(samples);
  out.timingsMs.emplace_back("samples", msSince(t0));

  t0 = Clock::now();
  FeedFieldOptions fopt;
  fopt.stencilRadius = settings.stencilMm;
  fopt.gammaSamples = static_cast<int>(settings.gammaSamples);
  // One rotation about the nozzle (and one IK branch) for the whole surface, the one with the
  // best worst-case w_PS: w_PS is nearly flat in gamma, so per-sample optima wander by up to
  // 0.8 rad between neighbours, a motion no path could follow (measured: replayed joint rates
  // ~800x the limits), while the motion planner keeps gamma continuous.
  fopt.singleFreeAngle = true;
  FeedField field = buildFeedField(samples.samples, machine, fopt, progress);
  if (!field.ok()) return fail(field);
  out.timingsMs.emplace_back("feed", msSince(t0));

  t0 = Clock::now();
  DriveDirectionOptions dopt;
  dopt.directions = static_cast<int>(settings.directions);
  dopt.beadWidth = options.beadWidth;
  dopt.maxFeed = options.maxFeed;
  dopt.forcedThetaDegrees = settings.thetaDegrees;
  DriveDirectionResult search = searchDriveDirection(samples.samples, field, dopt, progress);
  if (!search.ok()) return fail(search);
  out.timingsMs.emplace_back("direction", msSince(t0));

  // w_eff over the samples' heights (all options.layerHeight here).
  const EffectiveWidthTable table(options.beadWidth, options.layerHeight, options.layerHeight);
  const WidthFn width = table.function();
  const FeedFn feed = edgeFeed(field, samples.samples, options.maxFeed);
  IsoplanarOptions popt;
  popt.chordError = settings.chordErrorMm > 0 ? settings.chordErrorMm
                                              : std::min(0.5, options.layerHeight / 8);

  t0 = Clock::now();
  IsoplanarSurface prepared = prepareIsoplanarSurface(surface, samples.samples);
  if (!prepared.ok()) return fail(prepared);
  popt.thetaDegrees = search.thetaStarDegrees;
  IsoplanarResult planned = isoplanarPaths(prepared, width, popt, progress);
  if (!planned.ok()) return fail(planned);
  const IsoplanarTime time = estimateIsoplanarTime(planned, feed, options.maxFeed, options.travelSpeed);
  out.timingsMs.emplace_back("paths", msSince(t0));

  // The benchmark of Table 2: every other sampled direction planned and timed the same way.
  t0 = Clock::now();
  double benchTime = 0, benchPath = 0;
  size_t benchCount = 0;
  if (options.benchmark) {
    const size_t n = search.thetaDegrees.size();
    for (size_t i = 0; i < n; ++i) {
      if (std::abs(search.thetaDegrees[i] - search.thetaStarDegrees) < 1e-9) continue;
      if (!reportProgress(progress, "benchmark", double(i) / double(n))) {
        return fail(Outcome{Status::Cancelled, "cancelled"});
      }
      IsoplanarOptions o = popt;
      o.thetaDegrees = search.thetaDegrees[i];
      IsoplanarResult other = isoplanarPaths(prepared, width, o);
      if (!other.ok()) return fail(other);
      const IsoplanarTime t = estimateIsoplanarTime(other, feed, options.maxFeed, options.travelSpeed);
      benchTime += t.totalS;
      benchPath += t.pathMm;
      ++benchCount;
    }
    if (benchCount > 0) {
      benchTime /= double(benchCount);
      benchPath /= double(benchCount);
    }
  }
  out.timingsMs.emplace_back("benchmark", msSince(t0));

  // Surface paths with their curve tags (1-based within this surface, shifted to the print's).
  out.curves = static_cast<uint32_t>(planned.curves.size());
  out.paths = planned.paths;
  for (size_t p = 0; p < out.paths.size(); ++p) {
    SurfacePath& path = out.paths[p];
    path.curves.assign(path.points.size(), 0);
    if (p >= planned.pathPointCurve.size() || planned.pathPointCurve[p].size() != path.points.size()) continue;
    for (size_t k = 1; k < path.points.size(); ++k) {
      // The segment ending at point k lies on a curve when both its ends do.
      const uint32_t a = planned.pathPointCurve[p][k - 1], b = planned.pathPointCurve[p][k];
      if (a > 0 && a == b) path.curves[k] = a - 1 + options.firstCurve;
    }
  }

  // Side steps as the planner reports them (the shortened offset to the last plane left out).
  const double minStep = planned.minSideStep, maxStep = planned.maxSideStep;
  double widthSum = 0;
  size_t widthCount = 0;
  for (const NlCurve& c : planned.curves) {
    for (double w : c.width) {
      widthSum += w;
      ++widthCount;
    }
  }

  out.thetaDegrees = search.thetaStarDegrees;
  out.depositionRate = search.depositionRateAtTheta;
  out.pathMm = time.pathMm;
  out.estimatedTimeS = time.totalS;
  out.benchmarkTimeS = benchTime;
  out.benchmarkPathMm = benchPath;

  IsoplanarReport& r = out.report;
  r.thetaDeg = search.thetaStarDegrees;
  r.forced = settings.thetaDegrees >= 0;
  r.depositionRateMm3S = search.depositionRateAtTheta;
  for (size_t i = 0; i < search.thetaDegrees.size(); ++i) {
    r.curve.emplace_back(search.thetaDegrees[i], search.depositionRate[i]);
  }
  r.samples = search.samples;
  r.unreachable = search.unreachable;
  r.maxFeedMmS = options.maxFeed;
  // Assigned, not emplace()d: clang with libstdc++ decides a nested struct with default member
  // initializers is not default-constructible inside std::optional (the fuzz build is clang).
  r.paths = IsoplanarReport::Paths{};
  IsoplanarReport::Paths& rp = *r.paths;
  rp.bestSampledThetaDeg = search.thetaDegrees.empty() ? 0.0 : search.thetaDegrees[search.best];
  rp.pathMm = time.pathMm;
  rp.estimatedTimeS = time.totalS;
  rp.printS = time.printS;
  rp.joinsS = time.joinS;
  rp.travelS = time.travelS;
  rp.meanFeedMmS = time.meanFeed;
  rp.planes = planned.planes;
  rp.curves = planned.curves.size();
  rp.paths = planned.paths.size();
  rp.sideStepMinMm = minStep;
  rp.sideStepMaxMm = maxStep;
  rp.meanWidthMm = widthCount > 0 ? widthSum / double(widthCount) : 0.0;
  rp.chordErrorMm = popt.chordError;
  rp.beadWidthMm = options.beadWidth;
  rp.layerHeightMm = options.layerHeight;
  if (options.benchmark) r.benchmark = IsoplanarReport::Benchmark{benchTime, benchPath, benchCount};
  r.timingsMs = out.timingsMs;
  return out;
}

PlanarDirection planarIsoplanarDirection(const SliceResult& slices, const Settings& settings,
                                         const MachineProfile& machine,
                                         const ProgressFn& progress) {
  PlanarDirection out;
  const Clock::time_point t0 = Clock::now();
  const size_t nl = slices.layers.size();
  if (nl == 0) {
    return failed<PlanarDirection>(Status::EmptyInput, "no layers to fill");
  }
  const size_t layerCount = std::min<size_t>(nl, 24);
  double area = 0;
  std::vector<size_t> picked;
  for (size_t k = 0; k < layerCount; ++k) picked.push_back(layerCount == 1 ? 0 : k * (nl - 1) / (layerCount - 1));
  // Grid spacing: about 2 mm, coarser when the sections are large (at most ~20k samples).
  Eigen::Vector2d lo(1e300, 1e300), hi(-1e300, -1e300);
  for (size_t l : picked) {
    for (const ExPolygon2& isl : slices.layers[l].islands) {
      for (const Eigen::Vector2d& p : isl.contour) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
    }
  }
  if (lo.x() > hi.x()) {
    return failed<PlanarDirection>(Status::EmptyInput, "the layers have no sections to fill");
  }
  area = (hi - lo).prod() * double(picked.size());
  const double spacing = std::max(2.0, std::sqrt(area / 20000.0));
  std::vector<SurfaceSample> samples;
  for (size_t l : picked) {
    const SliceLayer& layer = slices.layers[l];
    for (const ExPolygon2& isl : layer.islands) {
      Eigen::Vector2d ilo(1e300, 1e300), ihi(-1e300, -1e300);
      for (const Eigen::Vector2d& p : isl.contour) {
        ilo = ilo.cwiseMin(p);
        ihi = ihi.cwiseMax(p);
      }
      for (double y = std::ceil(ilo.y() / spacing) * spacing; y <= ihi.y(); y += spacing) {
        for (double x = std::ceil(ilo.x() / spacing) * spacing; x <= ihi.x(); x += spacing) {
          if (!insideIsland(isl, {x, y})) continue;
          SurfaceSample smp;
          smp.position = slices.frame.toPart({x, y}, slices.minHeight + layer.top);
          smp.normal = slices.frame.d.normalized();
          smp.tangentU = slices.frame.e1;
          smp.tangentV = slices.frame.e2;
          smp.height = layer.top - layer.bottom;
          samples.push_back(smp);
        }
      }
    }
  }
  if (samples.empty()) {
    return failed<PlanarDirection>(Status::EmptyInput, "the layers' sections are too thin to sample for the iso-planar direction");
  }
  FeedFieldOptions fopt;
  fopt.stencilRadius = settings.isoplanar.stencilMm;
  fopt.gammaSamples = static_cast<int>(settings.isoplanar.gammaSamples);
  FeedField field = buildFeedField(samples, machine, fopt, progress);
  if (!field.ok()) return failed<PlanarDirection>(field);
  DriveDirectionOptions dopt;
  dopt.directions = static_cast<int>(settings.isoplanar.directions);
  dopt.beadWidth = settings.nozzleDiameter;
  dopt.maxFeed = settings.isoplanar.maxFeedMmS > 0 ? settings.isoplanar.maxFeedMmS : settings.infillSpeed;
  dopt.forcedThetaDegrees = settings.isoplanar.thetaDegrees;
  DriveDirectionResult search = searchDriveDirection(samples, field, dopt, progress);
  if (!search.ok()) return failed<PlanarDirection>(search);
  out.thetaDegrees = search.thetaStarDegrees;
  IsoplanarReport& r = out.report;
  r.thetaDeg = search.thetaStarDegrees;
  r.forced = settings.isoplanar.thetaDegrees >= 0;
  r.depositionRateMm3S = search.depositionRateAtTheta;
  for (size_t i = 0; i < search.thetaDegrees.size(); ++i) {
    r.curve.emplace_back(search.thetaDegrees[i], search.depositionRate[i]);
  }
  r.samples = search.samples;
  r.unreachable = search.unreachable;
  r.planar = IsoplanarReport::PlanarSampling{spacing, picked.size()};
  r.maxFeedMmS = dopt.maxFeed;
  r.timingsMs = {{"feed", field.ms}, {"direction", search.ms}, {"total", msSince(t0)}};
  return out;
}

void IsoplanarTotals::add(uint32_t layer, uint32_t region, double area, const IsoplanarFillResult& fill) {
  regions_.push_back({layer, region, fill.thetaDegrees, fill.depositionRate, fill.pathMm, fill.estimatedTimeS});
  path_ += fill.pathMm;
  time_ += fill.estimatedTimeS;
  rateArea_ += fill.depositionRate * area;
  area_ += area;
  if (area > largestArea_) {
    largestArea_ = area;
    largest_ = fill.report;
  }
}

std::optional<IsoplanarReport> IsoplanarTotals::report() const {
  if (!largest_) return std::nullopt;
  IsoplanarReport r = *largest_;
  r.largestRegionThetaDeg = r.thetaDeg;
  if (r.paths) {
    r.paths->pathMm = path_;
    r.paths->estimatedTimeS = time_;
  }
  r.depositionRateMm3S = area_ > 0 ? rateArea_ / area_ : 0.0;
  r.regions = regions_;
  return r;
}

}  // namespace omnislice
