// SPDX-License-Identifier: MIT
// The slice report as typed structs: what every method and stage measured, carried as numbers
// and turned into JSON once, at the edge (report_json.cpp: sliceReportJson). Each struct mirrors
// one object of the report JSON that README.md documents; the comments name its JSON key.
#pragma once
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/status.h"
#include "machine/machine.h"
#include "mesh/mesh.h"
#include "mesh/prepare_mesh.h"

namespace omnislice {

// Stage timings in the order they ran: (stage name, milliseconds).
using Timings = std::vector<std::pair<std::string, double>>;

// "support" (planar) and multidir's "supports": the projected-support generator (paper 000
// Section V) and what was printed of it.
struct SupportReport {
  double samplingMm = 0, angleDeg = 0, minDiameterMm = 0, roofMm = 0, mergeAngleDeg = 0;
  size_t samples = 0, pointOverhangs = 0, patchSamples = 0, landedOnModel = 0, landedOnPlatform = 0;
  size_t blocked = 0, merges = 0, struts = 0, roofs = 0;
  double riskyAreaMm2 = 0, strutVolumeMm3 = 0, roofVolumeMm3 = 0;
  double regionVolumeMm3 = 0;   // the support regions sliced on the layers
  double printedVolumeMm3 = 0;  // what the Support moves deposit
  double ms = 0;
};

// "isoplanar" (paper 003): theta* by the deposition rate and, when paths were planned on a
// surface, their figures.
// Sparse fill of curved layers (voxel, geodesic; pipeline/curved_stage.h).
struct CurvedSparseReport {
  double infillPercent = 100;          // the interior's density
  double shellMm = 0;                  // solid within this distance of the part's surface
  double interiorSpacingMm = 0;        // the interior spirals' spacing (0: no interior paths)
  size_t sparseRegions = 0;            // regions with an interior
  double areaMm2 = 0, interiorAreaMm2 = 0;  // of every part region, of their interiors
};

struct IsoplanarReport {
  double thetaDeg = 0;                            // theta* (or the forced angle)
  bool forced = false;
  double depositionRateMm3S = 0;                  // mean v_e at theta* (Eq. 10)
  std::vector<std::pair<double, double>> curve;   // (theta_deg, v_e) per sampled direction
  size_t samples = 0, unreachable = 0;
  double maxFeedMmS = 0;

  // Paths planned on a surface (planIsoplanarFill): absent on planar layers.
  struct Paths {
    double bestSampledThetaDeg = 0, pathMm = 0, estimatedTimeS = 0;
    double printS = 0, joinsS = 0, travelS = 0, meanFeedMmS = 0;
    size_t planes = 0, curves = 0, paths = 0;
    double sideStepMinMm = 0, sideStepMaxMm = 0, meanWidthMm = 0;
    double chordErrorMm = 0, beadWidthMm = 0, layerHeightMm = 0;
  };
  std::optional<Paths> paths;
  // The other sampled directions planned and timed the same way (Table 2); "benchmark": null
  // when not run.
  struct Benchmark {
    double meanEstimatedTimeS = 0, meanPathMm = 0;
    size_t directions = 0;
  };
  std::optional<Benchmark> benchmark;
  // Planar layers (planarIsoplanarDirection): the sample grid.
  struct PlanarSampling {
    double sampleSpacingMm = 0;
    size_t sampledLayers = 0;
  };
  std::optional<PlanarSampling> planar;
  // Many regions (the curved-layer methods' fill): the figures above are the largest region's,
  // with path_mm, estimated_time_s and deposition_rate_mm3_s summed (area-weighted) over all.
  struct Region {
    uint32_t layer = 0, region = 0;
    double thetaDeg = 0, depositionRateMm3S = 0, pathMm = 0, estimatedTimeS = 0;
  };
  std::optional<double> largestRegionThetaDeg;
  std::vector<Region> regions;
  // The surface method: its base and surface layer.
  struct Surface {
    int baseLayers = 0;
    double baseMm = 0, liftMm = 0;
    size_t surfaceVertices = 0, surfaceTriangles = 0;
    size_t orientationFallbacks = 0, tiltClamped = 0, gougingCorrections = 0, gougingUncorrected = 0;
  };
  std::optional<Surface> surface;
  Timings timingsMs;
};

// "voxel" (paper 001).
struct VoxelReport {
  size_t voxels = 0, solidVoxels = 0, supportVoxels = 0, missedVoxels = 0, missedBeforeSupports = 0;
  int supportRounds = 0;
  int fieldLayers = 0;
  std::string layerField;  // distance | steps | generations
  int smoothIterations = 0;
  int32_t layerFieldMax = 0;
  int layers = 0;          // curved layers with at least one path
  size_t surfaceLayers = 0, regions = 0, unfilledRegions = 0, paths = 0;
  std::string strategy, shadowScheme;
  double epsilon = 0, peelStep = 0, voxelWidthMm = 0, isoStep = 0, mmPerFieldUnit = 0, targetLayerMm = 0;
  struct Thickness {
    size_t samples = 0;
    double meanMm = 0, stdMm = 0, maxDeviationMm = 0;
    double histogramMinMm = 0, histogramBinMm = 0;
    std::vector<uint32_t> histogram;
    // Per printed layer in print order: min and max distance to the layers below (mm) and
    // whether it is a partial layer (bounded thickness).
    std::vector<double> layerMinMm, layerMaxMm;
    std::vector<uint8_t> layerPartial;
    double maxRatio = 0;           // voxel.max_thickness_ratio
    size_t partialLayers = 0;
  } thickness;
  size_t shadowChecks = 0, hullBuilds = 0;
  size_t orientationFallbacks = 0, tiltClamped = 0, gougingCorrections = 0, gougingUncorrected = 0;
  size_t axesFreed = 0;       // samples whose axis leans from its ideal for motion
  size_t reorderedPaths = 0;  // paths printed in another order to free self-blocked points
  double maxTiltDeg = 0, axisFreedomDeg = 0, gougingMs = 0;
  Timings timingsMs;  // voxelize, peeling, shadow, growth, extraction, spirals, toolpaths
};

// "geodesic" (paper 002).
struct GeodesicReport {
  size_t tets = 0, vertices = 0;
  std::string tetSource;  // input | mesher
  struct Mesher {
    double cellSizeMm = 0;
    size_t boundaryVertices = 0;
    double maxBoundaryDistanceMm = 0;
    size_t unsnapped = 0;
    double volumeRatio = 0, classifyMs = 0, stuffMs = 0, snapMs = 0;
  };
  std::optional<Mesher> mesher;  // null for a .tet input
  struct TetQualityReport {
    double volumeMm3 = 0, meanEdgeMm = 0, minDihedralDeg = 0, maxDihedralDeg = 0, minRadiusRatio = 0;
  } tetQuality;
  size_t sources = 0;
  double heatTime = 0, alignPasses = 0;  // alignPasses: those of the attempt kept
  // geodesic.align_retry_passes: whether a second attempt ran, what the first left out, and the
  // time of the attempt not kept.
  bool alignRetried = false;
  double alignFirstLeftOutMm = 0, alignRetryMs = 0;
  double baseBandMm = 0, maxThicknessRatio = 0, maxGeodesicMm = 0, intervalMm = 0, stepMinMm = 0;
  size_t layers = 0;
  int printedLayers = 0;
  size_t igds = 0;
  std::vector<double> isoValuesMm;
  size_t triangles = 0, interpolatedTriangles = 0;
  std::vector<double> overhangAvgDeg, overhangRatio, overhangMaxDeg;  // per layer
  double overhangAvgAllDeg = 0, overhangMaxLayerDeg = 0;
  struct Thickness {
    std::vector<double> meanMm, maxDeviationPercent, meanDeviationPercent;  // per layer
    double maxDeviationAllPercent = 0;
  } thickness;
  struct Tree {
    size_t nodes = 0, edges = 0;
    bool isTree = false;
    size_t branchPoints = 0, merges = 0, fallbackLinks = 0;
    uint32_t maxNodesPerLayer = 0;
  } tree;
  double nozzleAngleDeg = 0;
  size_t pcsPairsTested = 0;
  struct Sequence {
    std::string name;  // lpt | dpt | a3
    size_t retractions = 0;
    double airMoveMm = 0;
    bool collisionFree = true;
    size_t collidingNodes = 0, collidingLowerBound = 0, unavoidableNodes = 0;
    size_t criterion2Relaxed = 0;  // nodes printed with Criterion 2 relaxed
    double ms = 0;
  };
  std::string sequence;           // the chosen traversal
  std::vector<Sequence> traversals;  // lpt, dpt, a3
  size_t paths = 0, unfilledRegions = 0;
  size_t orientationFallbacks = 0, tiltClamped = 0;
  size_t axesFreed = 0;  // samples whose axis leans from its ideal for motion
  double axisFreedomDeg = 0;
  double maxTiltDeg = 0;
  size_t gougingCorrections = 0, gougingUncorrected = 0, skippedSegments = 0;
  size_t reorderedPaths = 0;  // paths printed in another order to free self-blocked points
  size_t nearIdealPaths = 0;  // paths printed with their ideal axes where others left tool path out
  double skippedMm = 0;
  std::optional<std::pair<int32_t, int32_t>> skippedLayers;  // [first, last], 0-based
  Timings timingsMs;
};

// "multidir" (paper 000).
struct MultidirReport {
  double jgBeforeMm2 = 0, jgAfterMm2 = 0, alphaMaxDeg = 0;
  std::string scheme, dof;
  std::optional<Eigen::Vector3d> rotationAxis;  // 4dof
  struct Part {
    size_t printIndex = 0;
    Eigen::Vector3d direction{0, 0, 1};
    std::optional<double> planeOffsetMm;  // the part's clipping plane (normal = direction); none
                                          // for the platform part
    double volumeMm3 = 0;
    size_t components = 0;
    double riskyAreaMm2 = 0;
    int layers = 0;
    bool sliced = false;  // false: an empty piece (no layers, no support or reach figures)
    double supportRegionMm3 = 0, reachAcrossMm = 0;
  };
  std::vector<Part> parts;
  double volumeMm3 = 0, capAreaMm2 = 0;
  bool supportsGenerated = false;
  double supportVolumeMm3 = 0;
  std::optional<SupportReport> supports;
  struct Search {
    size_t normals = 0, candidatesEvaluated = 0, candidatesChecked = 0, connectivityChecks = 0;
    size_t refusedFloating = 0, refusedSmall = 0, refusedSimilar = 0, beams = 0, levels = 0;
    size_t axesTried = 0, restartsRun = 0, perturbations = 0, perturbationsKept = 0;
    std::vector<double> jgPerLevel;
    size_t gridCells = 0;
    double cellMm = 0;
  } search;
  Timings timingsMs;  // the search's stages, then the pipeline's (decompose, clip, ...)
};

// "motion": the motion planner (core/motion).
struct MotionReport {
  size_t samples = 0, machineMoves = 0, subdivisions = 0, filteredOrientations = 0;
  size_t feedLimitedMoves = 0, safeRotations = 0;
  double maxJointStep = 0, poseCost = 0;
  std::optional<double> greedyPoseCost;  // null when not computed
  double minSingularity = 0, estimatedTimeS = 0;
};

// A program the pipeline made again with a remedy it applies itself (pipeline/soundness.h
// automaticRemedies) after the check found the first one unsound.
struct AttemptSection {
  std::string settings;               // the change, "key=value"
  std::string why;                    // what the remedy addresses
  bool sound = false;
  std::vector<std::string> failures;  // what still failed (empty when sound)
  double ms = 0;                      // the attempt's time: method, motion, program, check
};

// "verify": the program as made, simulated as `omnislice verify` does (PROGRAM-FORMAT.md), and
// judged sound or not (pipeline/soundness.h: inside >= 0.99, coverage >= 0.97 where the fill is
// solid, supported >= 0.99, no collision, no limit violated, no tool path left out).
struct VerifySection {
  std::string mode;                   // refuse | warn: what an unsound program meets
  double inside = 0, coverage = 0, supported = 0, supportedAll = 0;
  double surfaceReached = 0, surfaceReachMm = 0;  // share of the surface with a bead within reach
  size_t collisions = 0, limits = 0, samples = 0;
  size_t surfaceSamples = 0, unsupportedSamples = 0;  // judged for supported, and not supported
  double leftOutMm = 0;               // tool path the method left out
  // The bounds judged against (SoundnessCriteria), so viewers need not copy them.
  double minInside = 0, minCoverage = 0, minSupported = 0, minReached = 0;
  bool coverageJudged = false;        // the fill is solid (curved methods, or 100 % infill)
  bool sound = true;
  std::vector<std::string> failures;  // what fails, one phrase each ("56 samples collide ...")
  std::string statement;              // unsound: why and what would print it ("" when sound)
  // The programs made again after the one of the user's settings was unsound, in order; the
  // last one is delivered when it is sound (then this section is its check), else the first
  // program is (this section is that one's, the statement names what was tried).
  std::vector<AttemptSection> attempts;
  double ms = 0;
};

// What a method adds to the report: its own sections.
struct MethodReport {
  std::optional<VoxelReport> voxel;
  std::optional<GeodesicReport> geodesic;
  std::optional<MultidirReport> multidir;
  std::optional<IsoplanarReport> isoplanar;
  std::optional<CurvedSparseReport> sparseFill;  // voxel, geodesic with infill < 100
  std::optional<SupportReport> support;  // planar supports
  // support = auto with the planar method: the share of the part's surface that overhangs (Eq. 1
  // along the slicing direction at the support angle, faces on the platform left out), the share
  // above which auto prints supports, and what it chose.
  struct SupportAuto {
    double overhangPercent = 0, thresholdPercent = 0, overhangMm2 = 0;
    bool supports = false;
  };
  std::optional<SupportAuto> supportAuto;
};

// "mesh": the input as read, validated and placed.
struct InputReport {
  MeshInfo info;
  std::string format;                     // stl | obj | off | ply | 3mf | tet
  std::vector<std::string> readWarnings;  // appended to info's warnings
  Eigen::Matrix4d placement = Eigen::Matrix4d::Identity();
  BoundingBox placedBox;
};

// The whole report of one slice.
// method = auto: one candidate method's outcome.
struct AutoCandidate {
  std::string method;
  std::string status = "ok";          // "ok", or the error code that stopped it
  std::string message;                // the error, or why it stopped early
  bool stoppedEarly = false;          // dominated before its check: it could not win
  std::optional<VerifySection> verify;  // its check (figures only)
  double supportVolumeMm3 = 0, estimatedTimeS = 0, totalMs = 0;
};

// method = auto: every candidate in the order they ran, the one delivered and why.
struct AutoSection {
  std::vector<AutoCandidate> candidates;
  std::string chosen;   // a method name; "" when none made a program
  std::string reason;   // in words
};

struct SliceReport {
  std::string method, machine;
  MachineKind machineKind = MachineKind::Cartesian3;
  std::string programFormat, programExtension;
  int layers = 0;
  size_t slicedLayers = 0;
  double layerHeightMm = 0, pathMm = 0, extrusionMm = 0, travelMm = 0;
  size_t retractions = 0;
  double estimatedTimeS = 0;
  size_t moves = 0;
  MotionReport motion;
  MachineProfile machineProfile;
  Eigen::Vector3d direction{0, 0, 1};
  Eigen::Matrix4d placement = Eigen::Matrix4d::Identity();
  size_t openChains = 0;
  MethodReport sections;
  std::optional<VerifySection> verify;  // absent with verify = off
  double supportVolumeMm3 = 0;          // support the program prints (filament of its support moves)
  std::optional<AutoSection> autoChoice;  // method = auto
  std::string fill;
  std::vector<Warning> warnings;
  Timings timingsMs;
  InputReport mesh;
  std::vector<std::pair<std::string, std::string>> settings;  // listSettings()
};

// JSON of the report (README.md "slice"): keys as documented, non-finite numbers written as 0.
std::string sliceReportJson(const SliceReport& report);

// JSON of method = auto's section ("auto" in the report).
std::string autoSectionJson(const AutoSection& section);

// JSON of the input ("mesh" in the report; `omnislice info`), with extra timings when given.
std::string inputReportJson(const InputReport& input, const Timings& timingsMs = {});

}  // namespace omnislice
