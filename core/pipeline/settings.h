// SPDX-License-Identifier: MIT
// Every user-facing setting of the pipeline, with defaults, declared once in a table
// (settings_table.cpp: key, type, default, range, unit, help, choices). Parsing (setSetting),
// listing (listSettings: program headers, reports), the CLI's help and the page's settings schema
// (settingsSchemaJson, through the wasm API) all come from it, so a key means the same everywhere.
// Choices are parsed once into enum types.
#pragma once
#include <Eigen/Core>
#include <functional>
#include <optional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "common/memory_budget.h"
#include "common/status.h"
#include "geodesic/print_order.h"
#include "mesh/place_mesh.h"
#include "multidir/decomposition.h"
#include "pipeline/method.h"
#include "program/write_gcode.h"
#include "slice/plan_layers.h"
#include "voxel/growth_field.h"
#include "voxel/layer_field.h"

namespace omnislice {

// How layers are filled: auto (planar: walls + infill, voxel and geodesic: Fermat spirals,
// surface: iso-planar) | isoplanar (paper 003's paths) | spiral (voxel only).
enum class FillMode { Auto, Isoplanar, Spiral };

// Supports: auto (multidir: projected, planar: none) | none | projected.
enum class SupportMode { Auto, None, Projected };

// auto (rotary4: 4dof about its A axis, else 5dof) | 4dof | 5dof.
enum class MultidirDof { Auto, FourDof, FiveDof };

// What the pipeline does with the program it made: simulate it (the checks of `omnislice verify`)
// and refuse it when it is not sound (refuse), deliver it with a warning (warn), or not simulate
// (off). auto: refuse for the multi-axis methods, off for the planar method (a planar print
// without supports is what every 3-axis slicer delivers; verify it on request).
enum class VerifyMode { Auto, Refuse, Warn, Off };
// `repair`: auto = close a mesh that does not bound a solid (mesh/repair_mesh.h) for the methods
// that slice one; none = refuse it (open_mesh, non_manifold).
enum class RepairMode { Auto, None };

// The voxel method (paper 001): voxelisation, growing field, curved layers, Fermat spirals.
struct VoxelSettings {
  double widthMm = 0;                  // voxel width w, mm; 0 = 0.8 x nozzle (paper Section 6.2.1)
  GrowthStrategy strategy = GrowthStrategy::PgSpGcfa;  // gcfa | sp-gcfa | pg-gcfa | pg-sp-gcfa
  ShadowScheme shadow = ShadowScheme::RecursivePca;    // shadow prevention: incremental | recursive
  double peelStep = 1;                 // delta f of Algorithm 1, peeling sheets
  double epsilon = -1;                 // Definitions 2-3, voxel widths; < 0 = the field's default
  bool supports = false;               // add supports under missed voxels and grow again
  LayerField layerField = LayerField::Distance;  // curved layers are iso-surfaces of
                                                // (voxel/layer_field.h)
  double smoothIterations = 20;        // Jacobi smoothing passes over the layer field before
                                       // extraction (0 = the field as grown; 5 measured with the
                                       // steps field on a 30 mm Bunny: collisions 2,106 -> 167,
                                       // coverage 0.917 -> 0.925, supported 0.779 -> 0.739).
                                       // 20: rounder creases where growth fronts merge; with the
                                       // bounded thickness, on table5 at 40 mm (5 / 20 / 60
                                       // passes, verify's collisions): kitten (ply) 4,724 / 100 /
                                       // 195, fertility 10,512 / 729 / 610, yoga 55 / 22 / 1,296,
                                       // bunnyhead 31 / 0 / 0, topopt 31 / 42 / 138, kitten 11 /
                                       // 42 / 49; supported within 0.005
  double isoStep = 0;                  // curved-layer iso step in G units; 0 = from layerMm
  double layerMm = 0;                  // target curved-layer thickness, mm; 0 = w (0.8 x nozzle,
                                       // the paper's calibrated layer of Section 6.2.1)
  double maxThicknessRatio = 1.3;      // bounded thickness: partial layers where a curved layer
                                       // lies further than this x the target layer from the one
                                       // below (curved_layers.h maxThickness); 0 = off. 1.3
                                       // leaves room for the lateral step to the bead below
                                       // within verify's 1.5 h (Bunny, Yoga, Kitten at 40 mm on
                                       // table5: supported 0.71-0.90 -> 0.996-0.999)
  double platformRadiusMm = 0;         // platform disc radius; 0 = the part's footprint
  double maxVoxels = 3e6;              // refuse grids with more solid voxels
  double maxTiltDegrees = 0;           // nozzle axes lean at most this far from +Z; 0 = the
                                       // machine's (table5: its B range; robot6: 90)
};

// Iso-planar paths (paper 003): best drive-plane direction by the material deposition rate.
struct IsoplanarSettings {
  double thetaDegrees = -1;     // drive-plane angle in [0, 180); -1 = search theta* (Eq. 11)
  double directions = 180;      // theta samples over [0, 180) for the search (Algorithm 1)
  double chordErrorMm = 0;      // delta_c* of Eq. 12, mm; 0 = min(0.5 (paper Table 1), h / 8):
                                // a chord 0.5 mm off a 0.4 mm curved layer digs into the layer
                                // below (Bunny, voxel fill on table5: verify collisions 278 -> 39,
                                // coverage 0.985 -> 0.997 at 0.05 mm); on the 0.75 mm saddle
                                // layer h / 8 keeps theta*'s gain (15.6 -> 13.2 %) and raises
                                // supported 0.987 -> 0.994
  double stencilMm = 1;         // l_c of Eq. 7, mm
  double gammaSamples = 36;     // robot6: samples of the rotation about the nozzle (Eq. 6)
  double maxFeedMmS = 0;        // cap on the kinematic feed f*, mm/s; 0 = print_speed
  bool benchmark = true;        // plan every other sampled direction the same way and report
                                // their mean time and length (surface method)
};

// `method = surface`: an open surface printed as one layer on a planar support base.
struct SurfaceSettings {
  double baseMm = 2;            // thinnest support base under the surface layer, mm
};

// `method = geodesic` (paper 002): tet mesh, heat-method geodesic field from the platform,
// iso-geodesic distance surfaces (IGDS), skeleton tree, collision-aware print order.
struct GeodesicSettings {
  double intervalMm = 0;        // geodesic distance between IGDS (the layer), mm; 0 = layer_height
  double tetSizeMm = 0;         // tet mesher lattice spacing, mm; 0 = about target_tets tets
  double targetTets = 60000;    // tets the mesher aims at when tet_size_mm = 0
  double nozzleAngleDeg = 0;    // nozzle cone angle of the collision model (the paper's NA),
                                // degrees; 0 = the machine's nozzle cone half-angle
  double baseBandMm = 0;        // boundary vertices this close to the platform are the heat
                                // source, held at their height; 0 = a quarter interval
  double maxThicknessRatio = 0.7;  // iso-values stepped so the layers stand at most this many
                                // intervals apart where they meet the surface (99 % of it;
                                // surfaceLimitedIsoValues): the interval is the thickest layer
                                // there, as a layer height is; 0 = phi_i = i d (the paper)
  // Heat-method time step t as a multiple of h^2 (h the mean tet edge; the paper: t = h^2). A
  // longer diffusion also aligns fronts that merge, more weakly than alignPasses and at a cost:
  // at 30 h^2 (40 mm, table5) the kitten left 102 mm out instead of 770, but the bench bunny's
  // field took 2x as long (598 ms in wasm) for 13 % more layers.
  double heatTime = 1;
  // Smoothing passes over the heat's unit directions X before the Poisson step
  // (HeatGeodesicOptions::alignPasses; 0 = the paper). Where fronts merge, paper 002's kitten
  // failed on the "misalignment of the geodesics from the two branches" (its future work: adapt
  // the field so they align); 10 passes round those creases. On the nine shared closed models at
  // 40 mm, table5, with maxThicknessRatio 0.7 (left-out mm, before -> after, against heatTime 30
  // and ratio 1): kitten 102 -> 0, kitten (ply) 765 -> 343, fertility 4,149 -> 1,995, yoga 112 ->
  // 85, topopt 19 -> 0; sound 2 -> 5 of 9 for about the same number of layers; bench bunny 5.9 ->
  // 5.1 s native, field 308 -> 147 ms. 40 since 2026-12-01: with the tool path retrying its
  // left-out paths near their ideal axes and the axis freedom 25, the nine models at 40 mm
  // (table5 and robot6) are sound wherever they were at 10 (the Yoga now too), the layers
  // smoother for the machine: kitten table5 1.07 -> 0.69 h (rotary motion 78,492 -> 3,315 deg),
  // coin 2.02 -> 1.81 h, bunny 2.76 -> 2.08 h, bunnyhead 1.46 -> 1.18 h, topopt 2.28 -> 1.85 h.
  double alignPasses = 40;
  // Where those passes leave tool path out, the field, layers and tool path are made once more
  // with this many passes and the attempt leaving less out is kept (0, or not above alignPasses:
  // no retry). More passes round the creases further but are not better everywhere (40 mm,
  // table5, left-out mm at 10 / 30 / 40 / 50 passes: kitten (ply) 343 / 0 / 0 / 0 with supported
  // 0.992 / 0.990 / 0.988 at 30-50, yoga 85 / 1.7 / 0 / 0, fertility 1,995 / 817 / 552 / 417,
  // bunny 0 / 0.9 / 0.8 / 1.8; measured before the left-out paths were retried near their
  // ideal axes). With 40 passes the default, the retry takes 50.
  double alignRetryPasses = 50;
  TraversalKind sequence = TraversalKind::A3;  // print order: a3 (Algorithm 3) | lpt | dpt
  bool remesh = true;           // isotropic remeshing + Laplacian smoothing of the IGDS
};

// `method = multidir` (paper 000): the solid cut by a sequence of planes into parts, each printed
// with planar layers along its own direction (3+2 axes), the search of Section IV.
struct MultidirSettings {
  double alphaMaxDeg = 45;       // maximal self-supporting angle, degrees
  double w = 10;                 // parts smaller than V(M)/w are refused (Criterion IV)
  double offsetStepMm = 1;       // candidate plane offsets along each normal, mm
  double platformMarginMm = 5;   // Criterion III: the platform is the footprint grown by this, mm
  double maxTiltDeg = 0;         // 5dof: largest tilt of a part's direction from +Z, degrees;
                                 // 0 = the machine's (table5: its B range, robot6: 90)
  double stepAngleDeg = 0;       // 4dof: stepper angle, degrees; 0 = the machine's
  int samples = 250;             // candidate normals on the sphere (or circle, 4dof)
  int beamWidth = 8;             // b, beams per level
  int restarts = 3;              // 5dof beam: searches (at most) on spheres of normals turned
                                 // about Z; they stop once J_G <= 0.1 mm^2
  int perturbations = 60;        // beam: iterated local search moves on the refined planes
                                 // (0 = off); they stop once J_G <= 0.1 mm^2
  int axisSearch = 0;            // 4dof: > 0 = try this many horizontal rotation axes
  SearchScheme scheme = SearchScheme::Beam;  // beam | greedy | constrained
  MultidirDof dof = MultidirDof::Auto;
  double interfaceOverlap = 1.0; // an earlier part reaches across a later part's plane by this
                                 // fraction of (h/2)(1 - |cos beta|) (multidir_method.cpp); 0 = none,
                                 // 1 = as far as keeps its layers under the later part's first tips
};

// Supports under what stays risky (paper 000 Section V: projected supports). The multidir method
// projects them through its parts' subspaces; the planar method, printed along one direction,
// gets the same generator with no clipping plane (ordinary supports along d = +Z).
struct SupportSettings {
  SupportMode mode = SupportMode::Auto;
  double samplingMm = 0;         // R, overhang sampling interval, mm; 0 = 2.5 x nozzle + 1 (the
                                 // paper: 2 mm for a 0.4 mm nozzle, 3 mm for 0.8 mm)
  double angleDeg = 0;           // overhangs steeper than this need support, degrees; 0 =
                                 // multidir.alpha_max_deg (multidir) or 45 (planar)
  double lambda = 1e-6;          // Eq. 13, strut diameter growth with the torque above
  double minDiameterMm = 0;      // strut diameter floor, mm; 0 = 2 x line width
  int roofLayers = 2;            // solid support layers right under an overhang (roof)
  double mergeAngleDeg = 30;     // tree branches at most this far from the direction (0 = columns)
  double gapMm = 0;              // horizontal gap between support and the part, mm (0: the roof
                                 // meets the part's outer wall, which verify's 1.5 h reach needs)
  double autoSharePercent = 1;   // support = auto, planar: supports when more of the surface
                                 // than this overhangs, % of its area
};

struct Settings {
  Method method = Method::Planar;
  FillMode fill = FillMode::Auto;
  VoxelSettings voxel;
  IsoplanarSettings isoplanar;
  SurfaceSettings surface;
  GeodesicSettings geodesic;
  MultidirSettings multidir;
  SupportSettings support;
  std::string machine = "cartesian3";  // built-in machine profile name (builtinMachineNames())
  std::string machineJson;             // a user's machine profile (docs/MACHINES.md); overrides
                                       // `machine` when not empty
  // G-code kinds: the firmware's letter for an axis ("B=U,C=V"), over the profile's axis_letters
  // (checked against the machine's kind when it is resolved).
  std::map<std::string, std::string> axisLetters;
  GcodeDialect gcodeFlavor = GcodeDialect::Marlin;  // G-code kinds: marlin | reprap | klipper
  // G-code kinds: PNG thumbnails of the part for printer hosts, width x height each (empty = none).
  std::vector<std::pair<int, int>> thumbnails;
  RobotFormat robotFormat = RobotFormat::Csv;       // robot6: csv | urscript | rapid | krl
  int freeRotationSamples = 30;        // robot6: samples of the rotation about the nozzle axis
  bool smoothOrientations = true;      // paper 001 Section 5.2 orientation filter
  double orientationFilterDegrees = 10;  // filter where neighbouring axes differ by more
  // Curved layers (voxel, geodesic): how far a nozzle axis may lean from its ideal (Eq. 3 / the
  // layer normal) to keep the rotary axes still (motion/axis_freedom.h); 0 = the ideal axes, -1 =
  // the method's (effectiveAxisFreedom: geodesic 25, voxel 15). Measured on the 36 curved slices
  // of the shared models at 40 mm (2026-12-01): geodesic at 25, once its tool path retried the
  // paths it left out near their ideal axes (CurvedToolpathOptions::retryLeftOutNearIdeal), is
  // sound wherever it is at 15 and 13-45 % shorter on table5; voxel at 25 lost the Yoga (table5,
  // robot6) and the kitten (ply, robot6), which its remedies make sound at 15.
  double axisFreedomDegrees = -1;
  double chordTolerance = 0.01;        // mm, machine interpolation vs the part-frame path
  RepairMode repair = RepairMode::Auto;
  VerifyMode verify = VerifyMode::Auto;  // auto | refuse | warn | off (pipeline/soundness.h)
  // Programs made at most: when the check finds one unsound, again with the remedies the slicer
  // applies itself (soundness.h automaticRemedies, then curved supports: pipeline.cpp), the first
  // sound one delivered; 1 = only the program of these settings. 4: the geodesic method's two
  // thinner-layer remedies, then supports.
  int verifyAttempts = 4;
  // method = auto: candidates run on this many threads (0 = every core; 1 = one after another);
  // a wasm build without pthreads runs one.
  int threads = 0;
  // The memory budget in MB (common/memory_budget.h): a big structure estimated larger than this is
  // refused before it is allocated, with out_of_memory naming the figure and the setting.
  double memoryMb = kDefaultMemoryBudgetMb;
  PlaceOptions placement;
  Eigen::Vector3d direction{0, 0, 1};  // slicing direction d (normalised by setSetting), part frame

  double layerHeight = 0.2;       // mm, (0, nozzle]
  double firstLayerHeight = 0;    // mm, 0 = same as layerHeight
  double nozzleDiameter = 0.4;    // mm
  double lineWidth = 0;           // mm, 0 = 1.125 x nozzle
  double filamentDiameter = 1.75; // mm
  int walls = 2;                  // perimeters per island, >= 0
  int topLayers = 4;              // solid layers under a top surface
  int bottomLayers = 4;           // solid layers over a bottom surface
  double infillPercent = 20;      // sparse infill density, 0..100 (100 = solid)
  InfillPattern infillPattern = InfillPattern::Grid;
  SeamPlacement seam = SeamPlacement::Aligned;  // where planar wall loops start
  double infillAngleDegrees = 45; // angle of infill lines in the layer plane
  double infillOverlapPercent = 15;  // infill overlap into innermost wall, % of line width

  double printSpeed = 50;         // mm/s, inner walls, skin
  double outerWallSpeed = 30;     // mm/s
  double infillSpeed = 70;        // mm/s
  double firstLayerSpeed = 20;    // mm/s, all features on layer 0
  double travelSpeed = 150;       // mm/s
  double acceleration = 1500;     // mm/s^2, time estimate only (0 = ignore)
  double junctionDeviation = 0.013;  // mm, time estimate only: junction speeds of the look-ahead
  double retractLength = 0.8;     // mm of filament, 0 = off
  double retractSpeed = 35;       // mm/s of filament
  double retractMinTravel = 1.5;  // mm, shorter travels do not retract
  bool travelInside = true;        // planar travels keep inside the section (PlanarOptions)
  bool bridges = true;             // planar bridges (PlanarOptions)
  bool gapFill = true;             // planar gap fill between walls (PlanarOptions)
  double bridgeSpeed = 20;         // mm/s
  double bridgeFlowPercent = 80;   // % of a bead's filament
  double retractInsideMaxTravel = 10;  // mm, inside travels retract only when longer
  double nozzleTemperature = 210; // deg C
  double bedTemperature = 60;     // deg C
  double fanPercent = 100;        // part cooling fan, % (G-code machines; ProgramInfo)
  int fanOffLayers = 1;           // the first layers print with the fan off
  double bridgeFanPercent = 100;  // fan while printing bridges, %
  Eigen::Vector3d bedSize{220, 220, 250};  // mm, machine travel (limits for cartesian3)

  // Resolved line width.
  double effectiveLineWidth() const { return lineWidth > 0 ? lineWidth : 1.125 * nozzleDiameter; }
  // Resolved axis freedom (axisFreedomDegrees; -1 = the method's).
  double effectiveAxisFreedom() const {
    if (axisFreedomDegrees >= 0) return axisFreedomDegrees;
    return method == Method::Geodesic ? 25 : 15;
  }
  double effectiveFirstLayerHeight() const {
    return firstLayerHeight > 0 ? firstLayerHeight : layerHeight;
  }
};

// ---- the table ---------------------------------------------------------------------------------

enum class SettingType { Number, Integer, Boolean, Choice, Vector, Text };

// One setting as the table declares it.
struct SettingSpec {
  std::string key;                   // e.g. "layer_height", "voxel.width_mm"
  SettingType type = SettingType::Number;
  double min = 0, max = 0;           // Number, Integer: the inclusive range
  std::string unit;                  // "mm", "mm/s", "deg", "%", ... ("" for none)
  std::string help;                  // one line: what it does, what 0 or -1 means
  std::vector<std::string> choices;  // Choice: the values (canonical spellings)
  bool listed = true;                // in listSettings() (program header, report)
  std::optional<Method> onlyFor;     // listed only when this method is chosen
  std::function<Outcome(Settings&, const std::string&)> parse;  // checks and stores a text value
  std::function<std::string(const Settings&)> format;           // the value as listed
};

// Every setting, in the order listSettings() writes them.
const std::vector<SettingSpec>& settingSpecs();

// The spec of a key (aliases such as "nozzle" or "placement.up" accepted), or nullptr.
const SettingSpec* findSetting(const std::string& key);

// Set one setting by key ("layer_height", "walls", "infill", "placement.up", "direction", ...).
// value is text as typed on the command line. Unknown keys and out-of-range values give
// InvalidOption with a message naming the key and the accepted range or values.
Outcome setSetting(Settings& settings, const std::string& key, const std::string& value);

// Check cross-field consistency (e.g. layer height <= nozzle). InvalidOption on failure.
Outcome validateSettings(const Settings& settings);

// All settings as (key, value text) in the table's order, for program headers and reports
// (line width and first layer height resolved; method-specific choices only for that method).
std::vector<std::pair<std::string, std::string>> listSettings(const Settings& settings);

// The table as JSON for the page and the CLI's help: [{key, type (number | integer | boolean |
// choice | vector | text), default (text), min, max (number, integer), unit, help, choices
// (choice)}, ...] in the table's order.
std::string settingsSchemaJson();

// A number or a vector as settings are written ("0.2", "0,0,1": 10 significant digits).
std::string formatSettingNumber(double value);
std::string formatSettingVector(const Eigen::Vector3d& value);

// The planar tool-path options of the settings (slice/plan_layers.h).
PlanarOptions planarOptions(const Settings& settings);

}  // namespace omnislice
