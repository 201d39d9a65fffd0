// SPDX-License-Identifier: MIT
// The settings fields of the page, in one list (SETTINGS_SCHEMA): for each setting its key (the
// facade's setting key), label (units in it), type, default, bounds and choices, plus what only
// the page knows: its group (a sub-heading), testid, showIf (when the row shows) and sendIf (when
// a slice request carries it). The defaults and bounds are the core's (core/pipeline/settings.cpp;
// tests/js/wasm-machine.test.mjs compares them); when the core exports its settings schema, the
// list can be built from it with the page-only parts kept here. Also the direction presets, the
// built-in machines and the predicates the rows' showIf and sendIf use. No DOM: Node tests load it.

/** Direction presets (part-frame unit vectors, 'x,y,z'). Tilts lean +Z towards -Y or +X. */
export const DIRECTION_PRESETS = [
  { label: '+Z (planar)', value: '0,0,1' },
  { label: 'tilt 15° about X', value: dir(15, 'x') },
  { label: 'tilt 30° about X', value: dir(30, 'x') },
  { label: 'tilt 45° about X', value: dir(45, 'x') },
  { label: 'tilt 30° about Y', value: dir(30, 'y') },
  { label: 'tilt 45° about Y', value: dir(45, 'y') },
];

function dir(deg, axis) {
  const r = (deg * Math.PI) / 180;
  const s = Math.sin(r);
  const c = Math.cos(r);
  return parseDirection(axis === 'x' ? `0,${-s},${c}` : `${s},0,${c}`);
}

function round4(x) {
  return Math.round(x * 1e4) / 1e4;
}

/** Built-in machine profiles (names of core/program/machine.h builtinMachineNames()). */
export const MACHINE_CHOICES = [
  { label: 'cartesian3 (XYZ)', value: 'cartesian3' },
  { label: 'rotary4 (XYZ A)', value: 'rotary4' },
  { label: 'table5 (XYZ B C)', value: 'table5' },
  { label: 'robot6-ur5 (UR5 arm)', value: 'robot6-ur5' },
];

/**
 * The machine kind the settings select: the kind of the user's profile (machine_json) when one is
 * loaded, else that of the built-in machine ('robot6-ur5' -> 'robot6').
 */
export function selectedMachineKind(values) {
  if (values.machine_json) {
    try {
      const kind = JSON.parse(values.machine_json).kind;
      if (typeof kind === 'string') return kind.startsWith('robot6') ? 'robot6' : kind;
    } catch { /* checked when set */ }
  }
  return String(values.machine || '').startsWith('robot6') ? 'robot6' : values.machine;
}

const isRobot = (values) => selectedMachineKind(values) === 'robot6';
const isVoxel = (values) => values.method === 'voxel';
/** The geodesic method is chosen. */
export const isGeodesic = (values) => values.method === 'geodesic';
/** The multi-directional (3+2-axis) method is chosen. */
export const isMultidir = (values) => values.method === 'multidir';
/** Planar layers are printed: the planar method, the surface method's base, or the multidir
 *  method's parts. */
const isPlanar = (values) => !isVoxel(values) && !isGeodesic(values);
const isSurface = (values) => values.method === 'surface';
/** The iso-planar fill runs: the surface method, or fill = isoplanar on planar or curved layers. */
export const usesIsoplanar = (values) => isSurface(values) || values.fill === 'isoplanar';

/**
 * Field schema: key (the facade's setting key), label, type, default and bounds. Units in labels.
 * Groups render as sub-headings. Optional: testid (instead of setting-<key>), showIf(values)
 * (the row is hidden when false), sendIf(values) (the value is left out of slice requests when
 * false, e.g. the voxel method's settings for a planar slice), hidden (never rendered; set by
 * code, e.g. a loaded file).
 */
export const SETTINGS_SCHEMA = [
  { group: 'Machine', key: 'machine', label: 'machine', type: 'select', value: 'cartesian3', testid: 'machine',
    options: MACHINE_CHOICES },
  { group: 'Machine', key: 'gcode_flavor', label: 'G-code flavour', type: 'select', value: 'marlin', testid: 'gcode-flavor',
    options: [{ label: 'Marlin', value: 'marlin' }, { label: 'RepRapFirmware', value: 'reprap' }, { label: 'Klipper', value: 'klipper' }],
    showIf: (v) => !isRobot(v) },
  { group: 'Machine', key: 'robot_format', label: 'robot program', type: 'select', value: 'csv', testid: 'robot-format',
    options: [{ label: 'joint CSV (.csv)', value: 'csv' }, { label: 'URScript (.script)', value: 'urscript' }],
    showIf: isRobot },
  { group: 'Machine', key: 'machine_json', label: 'machine profile (JSON)', type: 'json', value: '', hidden: true },
  { group: 'Slicing', key: 'method', label: 'method', type: 'select', value: 'planar',
    options: [{ label: 'planar layers', value: 'planar' }, { label: 'voxel (curved layers)', value: 'voxel' },
      { label: 'surface (open surface, one layer on a base)', value: 'surface' },
      { label: 'geodesic (curved layers of a tet mesh)', value: 'geodesic' },
      { label: 'multi-directional (3+2-axis parts by planar clipping)', value: 'multidir' }] },
  { group: 'Slicing', key: 'fill', label: 'fill', type: 'select', value: 'auto', testid: 'setting-fill',
    options: [{ label: 'auto', value: 'auto' }, { label: 'iso-planar (paper 003)', value: 'isoplanar' }, { label: 'spiral', value: 'spiral' }] },
  // The geodesic method's interval defaults to the layer height.
  { group: 'Slicing', key: 'layer_height', label: 'layer height (mm)', type: 'number', value: 0.2, min: 0.02, max: 2, step: 0.01,
    showIf: (v) => !isVoxel(v) },
  { group: 'Slicing', key: 'nozzle', label: 'nozzle (mm)', type: 'number', value: 0.4, min: 0.1, max: 2, step: 0.05 },
  { group: 'Slicing', key: 'line_width', label: 'line width (mm, 0 = auto)', type: 'number', value: 0, min: 0, max: 3, step: 0.01 },
  { group: 'Slicing', key: 'walls', label: 'walls', type: 'integer', value: 2, min: 0, max: 20, step: 1,
    showIf: isPlanar },
  { group: 'Slicing', key: 'top_layers', label: 'top layers', type: 'integer', value: 4, min: 0, max: 50, step: 1,
    showIf: isPlanar },
  { group: 'Slicing', key: 'bottom_layers', label: 'bottom layers', type: 'integer', value: 4, min: 0, max: 50, step: 1,
    showIf: isPlanar },
  { group: 'Slicing', key: 'infill', label: 'infill (%)', type: 'number', value: 20, min: 0, max: 100, step: 1,
    showIf: isPlanar },
  { group: 'Slicing', key: 'infill_pattern', label: 'infill pattern', type: 'select', value: 'grid',
    options: [{ label: 'grid', value: 'grid' }, { label: 'lines', value: 'lines' }],
    showIf: isPlanar },
  { group: 'Slicing', key: 'direction', label: 'slicing direction', type: 'direction', value: '0,0,1',
    showIf: (v) => isPlanar(v) && !isMultidir(v) },
  // The voxel method (paper 001): conservative voxels, growing field, curved layers.
  { group: 'Voxel', key: 'voxel.width_mm', label: 'voxel width (mm, 0 = 0.8 × nozzle)', type: 'number', value: 0, min: 0, max: 50, step: 0.05,
    testid: 'voxel-width', showIf: isVoxel, sendIf: isVoxel },
  { group: 'Voxel', key: 'voxel.strategy', label: 'growth strategy', type: 'select', value: 'pg-sp-gcfa', testid: 'voxel-strategy',
    options: [{ label: 'GCFA', value: 'gcfa' }, { label: 'SP-GCFA', value: 'sp-gcfa' }, { label: 'PG-GCFA', value: 'pg-gcfa' },
      { label: 'PG-SP-GCFA', value: 'pg-sp-gcfa' }],
    showIf: isVoxel, sendIf: isVoxel },
  { group: 'Voxel', key: 'voxel.shadow', label: 'shadow prevention', type: 'select', value: 'recursive', testid: 'voxel-shadow',
    options: [{ label: 'recursive (PCA split)', value: 'recursive' }, { label: 'incremental (Dijkstra)', value: 'incremental' }],
    showIf: (v) => isVoxel(v) && v['voxel.strategy'].includes('sp-'), sendIf: isVoxel },
  { group: 'Voxel', key: 'voxel.peel_step', label: 'peel step Δf', type: 'number', value: 1, min: 0.01, max: 1000, step: 0.5,
    testid: 'voxel-peel-step', showIf: (v) => isVoxel(v) && v['voxel.strategy'].startsWith('pg-'), sendIf: isVoxel },
  { group: 'Voxel', key: 'voxel.epsilon', label: 'hull tolerance ε (voxel widths, −1 = default)', type: 'number', value: -1, min: -1, max: 2, step: 0.1,
    testid: 'voxel-epsilon', showIf: isVoxel, sendIf: isVoxel },
  { group: 'Voxel', key: 'voxel.layer_field', label: 'layers follow', type: 'select', value: 'distance', testid: 'voxel-layer-field',
    options: [{ label: 'growth distance', value: 'distance' }, { label: 'growth steps (G)', value: 'steps' },
      { label: 'generations from the platform', value: 'generations' }],
    showIf: isVoxel, sendIf: isVoxel },
  { group: 'Voxel', key: 'voxel.smooth', label: 'layer field smoothing (passes)', type: 'integer', value: 5, min: 0, max: 200, step: 1,
    testid: 'voxel-smooth', showIf: isVoxel, sendIf: isVoxel },
  { group: 'Voxel', key: 'voxel.layer_mm', label: 'layer thickness (mm, 0 = voxel width)', type: 'number', value: 0, min: 0, max: 5, step: 0.05,
    testid: 'voxel-layer-mm', showIf: isVoxel, sendIf: isVoxel },
  { group: 'Voxel', key: 'voxel.iso_step', label: 'iso step (field units, 0 = from the thickness)', type: 'number', value: 0, min: 0, max: 100, step: 0.1,
    testid: 'voxel-iso-step', showIf: isVoxel, sendIf: isVoxel },
  { group: 'Voxel', key: 'voxel.max_tilt_deg', label: 'max nozzle tilt (°, 0 = machine)', type: 'number', value: 0, min: 0, max: 180, step: 5,
    testid: 'voxel-max-tilt', showIf: isVoxel, sendIf: isVoxel },
  { group: 'Voxel', key: 'voxel.supports', label: 'supports under missed voxels', type: 'checkbox', value: false,
    testid: 'voxel-supports', showIf: isVoxel, sendIf: isVoxel },
  { group: 'Voxel', key: 'voxel.platform_radius_mm', label: 'platform radius (mm, 0 = footprint)', type: 'number', value: 0, min: 0, max: 5000, step: 1,
    testid: 'voxel-platform-radius', showIf: isVoxel, sendIf: isVoxel },
  { group: 'Voxel', key: 'voxel.max_voxels', label: 'max solid voxels', type: 'integer', value: 3000000, min: 1000, max: 1000000000, step: 100000,
    testid: 'voxel-max-voxels', showIf: isVoxel, sendIf: isVoxel },
  // Iso-planar paths (paper 003): the drive-plane direction theta* of the best deposition rate.
  { group: 'Iso-planar', key: 'isoplanar.theta_deg', label: 'drive-plane direction θ (°, −1 = search θ*)', type: 'number', value: -1, min: -1, max: 179.99, step: 1,
    testid: 'iso-theta', showIf: usesIsoplanar, sendIf: usesIsoplanar },
  { group: 'Iso-planar', key: 'isoplanar.directions', label: 'directions searched (over 180°)', type: 'integer', value: 180, min: 1, max: 3600, step: 1,
    testid: 'iso-directions', showIf: usesIsoplanar, sendIf: usesIsoplanar },
  { group: 'Iso-planar', key: 'isoplanar.chord_error_mm', label: 'chord error (mm, 0 = auto: min(0.5, layer/8))', type: 'number', value: 0, min: 0, max: 10, step: 0.05,
    testid: 'iso-chord-error', showIf: usesIsoplanar, sendIf: usesIsoplanar },
  { group: 'Iso-planar', key: 'isoplanar.benchmark', label: 'benchmark over all directions', type: 'checkbox', value: true,
    testid: 'iso-benchmark', showIf: usesIsoplanar, sendIf: usesIsoplanar },
  { group: 'Iso-planar', key: 'surface.base_mm', label: 'support base under the surface (mm)', type: 'number', value: 2, min: 0.1, max: 500, step: 0.5,
    testid: 'surface-base', showIf: isSurface, sendIf: isSurface },
  // The geodesic method (paper 002): tet mesh, heat-method geodesic field, iso-geodesic distance
  // surfaces (IGDS), skeleton tree and print sequence (core/pipeline/settings.cpp: names, ranges).
  { group: 'Geodesic', key: 'geodesic.interval_mm', label: 'IGDS interval (mm, 0 = layer height)', type: 'number', value: 0, min: 0, max: 20, step: 0.05,
    testid: 'geodesic-interval', showIf: isGeodesic, sendIf: isGeodesic },
  { group: 'Geodesic', key: 'geodesic.tet_size_mm', label: 'tet size (mm, 0 = from the target count)', type: 'number', value: 0, min: 0, max: 100, step: 0.1,
    testid: 'geodesic-tet-size', showIf: isGeodesic, sendIf: isGeodesic },
  { group: 'Geodesic', key: 'geodesic.target_tets', label: 'target tets', type: 'integer', value: 60000, min: 100, max: 3000000, step: 1000,
    testid: 'geodesic-target-tets', showIf: (v) => isGeodesic(v) && v['geodesic.tet_size_mm'] === 0, sendIf: isGeodesic },
  { group: 'Geodesic', key: 'geodesic.base_band_mm', label: 'base band (mm, the heat source: the part this close to the platform; 0 = a quarter interval)', type: 'number', value: 0, min: 0, max: 20, step: 0.1,
    testid: 'geodesic-base-band', showIf: isGeodesic, sendIf: isGeodesic },
  { group: 'Geodesic', key: 'geodesic.max_thickness_ratio', label: 'thickest layer at the surface (× interval; 0 = uniform steps as in the paper)', type: 'number', value: 1, min: 0, max: 3, step: 0.05,
    testid: 'geodesic-max-thickness', showIf: isGeodesic, sendIf: isGeodesic },
  { group: 'Geodesic', key: 'geodesic.nozzle_angle_deg', label: 'nozzle angle (°, 0 = the machine\'s cone)', type: 'number', value: 0, min: 0, max: 89, step: 1,
    testid: 'geodesic-nozzle-angle', showIf: isGeodesic, sendIf: isGeodesic },
  { group: 'Geodesic', key: 'geodesic.sequence', label: 'print sequence', type: 'select', value: 'a3', testid: 'geodesic-sequence',
    options: [{ label: 'A3 (collision-aware, fewer air moves)', value: 'a3' }, { label: 'LPT (layer by layer)', value: 'lpt' },
      { label: 'DPT (branch by branch)', value: 'dpt' }],
    showIf: isGeodesic, sendIf: isGeodesic },
  { group: 'Geodesic', key: 'geodesic.remesh', label: 'remesh and smooth the IGDS', type: 'checkbox', value: true,
    testid: 'geodesic-remesh', showIf: isGeodesic, sendIf: isGeodesic },
  // The multi-directional method (paper 000): clipping planes by a beam-guided search, each part
  // printed along its plane's normal (core/pipeline/settings.cpp: names, ranges).
  { group: 'Multi-directional', key: 'multidir.alpha_max_deg', label: 'self-supporting angle α_max (°)', type: 'number', value: 45, min: 1, max: 89, step: 1,
    testid: 'multidir-alpha', showIf: isMultidir, sendIf: isMultidir },
  { group: 'Multi-directional', key: 'multidir.w', label: 'smallest part w (parts ≥ volume / w)', type: 'number', value: 10, min: 1, max: 1000, step: 1,
    testid: 'multidir-w', showIf: isMultidir, sendIf: isMultidir },
  { group: 'Multi-directional', key: 'multidir.scheme', label: 'search', type: 'select', value: 'beam', testid: 'multidir-scheme',
    options: [{ label: 'beam-guided', value: 'beam' }, { label: 'greedy', value: 'greedy' },
      { label: 'constrained greedy', value: 'constrained' }],
    showIf: isMultidir, sendIf: isMultidir },
  { group: 'Multi-directional', key: 'multidir.beam_width', label: 'beam width b', type: 'integer', value: 8, min: 1, max: 100, step: 1,
    testid: 'multidir-beam-width', showIf: (v) => isMultidir(v) && v['multidir.scheme'] === 'beam', sendIf: isMultidir },
  { group: 'Multi-directional', key: 'multidir.restarts', label: 'restarts (5 DOF beam, normals turned)', type: 'integer', value: 3, min: 1, max: 64, step: 1,
    testid: 'multidir-restarts', showIf: (v) => isMultidir(v) && v['multidir.scheme'] === 'beam', sendIf: isMultidir },
  { group: 'Multi-directional', key: 'multidir.perturbations', label: 'local search moves (beam, 0 = off)', type: 'integer', value: 60, min: 0, max: 10000, step: 10,
    testid: 'multidir-perturbations', showIf: (v) => isMultidir(v) && v['multidir.scheme'] === 'beam', sendIf: isMultidir },
  { group: 'Multi-directional', key: 'multidir.dof', label: 'DOF mode', type: 'select', value: 'auto', testid: 'multidir-dof',
    options: [{ label: 'auto (rotary4: 4 DOF, else 5 DOF)', value: 'auto' }, { label: '4 DOF (one rotary axis)', value: '4dof' },
      { label: '5 DOF', value: '5dof' }],
    showIf: isMultidir, sendIf: isMultidir },
  { group: 'Multi-directional', key: 'multidir.interface_overlap', label: 'reach across later parts\' planes (× the safe depth, 0 = flush)', type: 'number', value: 0.8, min: 0, max: 1, step: 0.1,
    testid: 'multidir-interface-overlap', showIf: isMultidir, sendIf: isMultidir },
  { group: 'Multi-directional', key: 'multidir.samples', label: 'candidate normals', type: 'integer', value: 250, min: 4, max: 20000, step: 10,
    testid: 'multidir-samples', showIf: isMultidir, sendIf: isMultidir },
  { group: 'Multi-directional', key: 'multidir.axis_search', label: 'rotation axes searched (4 DOF, 0 = the machine\'s)', type: 'integer', value: 0, min: 0, max: 3600, step: 1,
    testid: 'multidir-axis-search', showIf: (v) => isMultidir(v) && (v['multidir.dof'] === '4dof' || (v['multidir.dof'] === 'auto' && selectedMachineKind(v) === 'rotary4')),
    sendIf: isMultidir },
  // Supports (paper 000 Section V): projected through the multidir parts' subspaces, or along +Z
  // for a planar print (core/pipeline/settings.h SupportSettings).
  { group: 'Supports', key: 'support', label: 'supports', type: 'select', value: 'auto', testid: 'support-mode',
    options: [{ label: 'auto (multidir: projected, planar: none)', value: 'auto' }, { label: 'none', value: 'none' },
      { label: 'projected', value: 'projected' }],
    showIf: isPlanar, sendIf: isPlanar },
  { group: 'Supports', key: 'support.sampling_mm', label: 'overhang sampling R (mm, 0 = from the nozzle)', type: 'number', value: 0, min: 0, max: 50, step: 0.5,
    testid: 'support-sampling', showIf: (v) => isPlanar(v) && v.support !== 'none', sendIf: isPlanar },
  { group: 'Supports', key: 'support.merge_angle_deg', label: 'tree branch angle (deg, 0 = straight columns)', type: 'number', value: 30, min: 0, max: 60, step: 5,
    testid: 'support-merge', showIf: (v) => isPlanar(v) && v.support !== 'none', sendIf: isPlanar },
  { group: 'Supports', key: 'support.roof_layers', label: 'solid roof layers under an overhang', type: 'integer', value: 2, min: 0, max: 100, step: 1,
    testid: 'support-roof', showIf: (v) => isPlanar(v) && v.support !== 'none', sendIf: isPlanar },
  { group: 'Supports', key: 'support.gap_mm', label: 'gap to the part (mm)', type: 'number', value: 0, min: 0, max: 5, step: 0.05,
    testid: 'support-gap', showIf: (v) => isPlanar(v) && v.support !== 'none', sendIf: isPlanar },
  { group: 'Speed', key: 'print_speed', label: 'print speed (mm/s)', type: 'number', value: 50, min: 1, max: 1000, step: 1 },
  { group: 'Speed', key: 'travel_speed', label: 'travel speed (mm/s)', type: 'number', value: 150, min: 1, max: 2000, step: 1 },
  { group: 'Speed', key: 'retract_length', label: 'retract (mm)', type: 'number', value: 0.8, min: 0, max: 20, step: 0.1 },
  { group: 'Placement', key: 'fit_mm', label: 'fit largest side (mm, 0 = off)', type: 'number', value: 0, min: 0, max: 1000, step: 1 },
  { group: 'Placement', key: 'scale', label: 'scale', type: 'number', value: 1, min: 0.0001, max: 10000, step: 0.1 },
  { group: 'Placement', key: 'up', label: 'up axis of the file', type: 'select', value: 'z',
    options: ['z', '-z', 'y', '-y', 'x', '-x'].map((v) => ({ label: v.startsWith('-') ? `−${v.slice(1).toUpperCase()}` : `+${v.toUpperCase()}`, value: v })) },
  { group: 'Placement', key: 'rotate_x_deg', label: 'rotate X (°)', type: 'number', value: 0, min: -360, max: 360, step: 15 },
  { group: 'Placement', key: 'rotate_y_deg', label: 'rotate Y (°)', type: 'number', value: 0, min: -360, max: 360, step: 15 },
  { group: 'Placement', key: 'rotate_z_deg', label: 'rotate Z (°)', type: 'number', value: 0, min: -360, max: 360, step: 15 },
  { group: 'Placement', key: 'center', label: 'centre on the plate', type: 'checkbox', value: true },
  { group: 'Motion', key: 'motion.free_rotation_samples', label: 'free-rotation samples (robot)', type: 'integer', value: 30, min: 1, max: 360, step: 1,
    showIf: isRobot },
  { group: 'Motion', key: 'motion.smooth_orientations', label: 'smooth orientations', type: 'checkbox', value: true },
  { group: 'Motion', key: 'motion.filter_deg', label: 'orientation filter above (°)', type: 'number', value: 10, min: 0, max: 180, step: 1 },
  { group: 'Motion', key: 'motion.chord_tolerance', label: 'chord tolerance (mm)', type: 'number', value: 0.01, min: 0.0001, max: 10, step: 0.001 },
];

/**
 * Parse a direction 'x,y,z' into a normalised string, or null when it is not three finite numbers
 * with a non-zero length.
 */
export function parseDirection(text) {
  const parts = String(text).split(/[\s,;]+/).filter(Boolean).map(Number);
  if (parts.length !== 3 || !parts.every(Number.isFinite)) return null;
  const len = Math.hypot(...parts);
  if (!(len > 1e-9)) return null;
  return parts.map((x) => round4(x / len)).join(',');
}
