// SPDX-License-Identifier: MIT
// The settings fields of the page. What a setting is (its default, range, unit, help and accepted
// choices) is the core's settings table (core/pipeline/settings_table.cpp), exported by the engine
// (slicer.settingsSchema()); PAGE_FIELDS keeps only what the page alone knows: the rows' order,
// groups, labels, input types, steps, testids, when a row shows and when a slice request carries
// its value, and the choices' display labels. settingsFields(coreSchema) joins the two into the
// fields the settings model and panel use (at start-up, web/main.js, and in the tests) and fails
// on a page field the core does not know, so drift shows at once. Also the direction presets and
// the predicates the rows' showIf and sendIf use. No DOM: Node tests load it.

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
 * The page's part of each settings field, in the panel's order: group (a sub-heading), key (the
 * facade's setting key), label (units in it) and optionally: core (the core table's key when the
 * page uses an alias), type (select, checkbox, direction, json; integer where the page wants whole
 * numbers of a core number; text for one line of free text; else the core's number or integer), step,
 * placeholder (text), testid (instead of
 * setting-<key>), labels ({choice: display label}, in display order), showIf(values) (the row is
 * hidden when false), sendIf(values) (the value is left out of slice requests when false, e.g. the
 * voxel method's settings for a planar slice), hidden (never rendered; set by code, e.g. a loaded
 * file).
 */
export const PAGE_FIELDS = [
  { group: 'Machine', key: 'machine', label: 'machine', type: 'select', testid: 'machine',
    labels: { cartesian3: 'cartesian3 (XYZ)', rotary4: 'rotary4 (XYZ A)', table5: 'table5 (XYZ B C)', head4: 'head4 (XYZ C, a tilted nozzle turns)', head5: 'head5 (XYZ B C, the head tilts)', 'robot6-ur5': 'robot6-ur5 (UR5 arm, paper 003 joint speeds)', 'robot6-ur5-rated': 'robot6-ur5-rated (UR5 arm, rated joint speeds)', 'robot6-irb1200': 'robot6-irb1200 (ABB IRB 1200 arm)', 'robot6-kr6': 'robot6-kr6 (KUKA KR 6 arm)' } },
  { group: 'Machine', key: 'gcode_flavor', label: 'G-code flavour', type: 'select', testid: 'gcode-flavor',
    labels: { marlin: 'Marlin', reprap: 'RepRapFirmware', klipper: 'Klipper' },
    showIf: (v) => !isRobot(v) },
  { group: 'Machine', key: 'robot_format', label: 'robot program', type: 'select', testid: 'robot-format',
    labels: { csv: 'joint CSV (.csv)', urscript: 'URScript (.script)', rapid: 'ABB RAPID (.mod)', krl: 'KUKA KRL (.src)' },
    showIf: isRobot },
  // The firmware's letters for the machine's axes (e.g. a Duet's rotary axes U and V); the core
  // checks them against the machine and the program header records them (PROGRAM-FORMAT.md).
  { group: 'Machine', key: 'axis_letters', label: 'firmware axis letters (empty = X Y Z A B C)', type: 'text',
    placeholder: 'B=U,C=V', showIf: (v) => !isRobot(v) },
  // PNG pictures of the part in the G-code, for printer hosts' file lists (PrusaSlicer's block).
  { group: 'Machine', key: 'thumbnails', label: 'thumbnails for the printer host (e.g. 16x16,220x124)', type: 'text',
    placeholder: '16x16,220x124', showIf: (v) => !isRobot(v) },
  { group: 'Machine', key: 'machine_json', label: 'machine profile (JSON)', type: 'json', hidden: true },
  { group: 'Slicing', key: 'method', label: 'method', type: 'select',
    labels: { planar: 'planar layers', voxel: 'voxel (curved layers)', surface: 'surface (open surface, one layer on a base)',
      geodesic: 'geodesic (curved layers of a tet mesh)', multidir: 'multi-directional (3+2-axis parts by planar clipping)',
      auto: 'auto (every method the machine takes, checked; the best)' } },
  { group: 'Slicing', key: 'fill', label: 'fill', type: 'select', testid: 'setting-fill',
    labels: { auto: 'auto', isoplanar: 'iso-planar (paper 003)', spiral: 'spiral' } },
  // The program is simulated before it is written (core/pipeline/soundness.h): an unsound one is
  // refused with why and what would print the model, unless the user asks for it anyway.
  { group: 'Slicing', key: 'verify', label: 'check the program by simulation', type: 'select', testid: 'setting-verify',
    labels: {
      auto: 'auto (multi-axis: refuse unsound programs)', refuse: 'refuse unsound programs',
      warn: 'write unsound programs with a warning', off: 'off',
    } },
  // An unsound program is made again with the remedies the core applies itself (the report's
  // verify.attempts); the first sound one is delivered with a `remedied` warning.
  { group: 'Slicing', key: 'verify_attempts', label: 'programs made at most when one is not sound (1 = no second attempt)',
    type: 'integer', step: 1, testid: 'setting-verify-attempts', showIf: (v) => v.verify !== 'off' },
  // A structure estimated larger is refused with out_of_memory naming this setting (the slicer's
  // worker is then replaced, so the page goes on).
  { group: 'Slicing', key: 'memory_mb', label: 'memory budget (MB; a tab\'s wasm heap ends at 4096)', step: 64 },
  // The geodesic method's interval defaults to the layer height.
  { group: 'Slicing', key: 'layer_height', label: 'layer height (mm)', step: 0.01,
    showIf: (v) => !isVoxel(v) },
  // 'nozzle' is the core's alias of nozzle_diameter; the page keeps sending 'nozzle'.
  { group: 'Slicing', key: 'nozzle', core: 'nozzle_diameter', label: 'nozzle (mm)', step: 0.05 },
  { group: 'Slicing', key: 'line_width', label: 'line width (mm, 0 = auto)', step: 0.01 },
  // Every method: voxel and geodesic keep a solid shell this thick and fill the inside sparsely.
  { group: 'Slicing', key: 'walls', label: 'walls', step: 1 },
  { group: 'Slicing', key: 'top_layers', label: 'top layers', step: 1 },
  { group: 'Slicing', key: 'bottom_layers', label: 'bottom layers', step: 1 },
  { group: 'Slicing', key: 'infill', label: 'infill (%)', step: 1 },
  { group: 'Slicing', key: 'infill_pattern', label: 'infill pattern', type: 'select',
    labels: { grid: 'grid', lines: 'lines' },
    showIf: isPlanar },
  { group: 'Slicing', key: 'seam', label: 'seam', type: 'select',
    labels: { aligned: 'aligned', nearest: 'nearest', sharpest: 'sharpest corner', random: 'random' },
    showIf: isPlanar },
  { group: 'Slicing', key: 'gap_fill', label: 'gap fill', type: 'checkbox', showIf: isPlanar },
  { group: 'Slicing', key: 'direction', label: 'slicing direction', type: 'direction',
    showIf: (v) => isPlanar(v) && !isMultidir(v) },
  // The voxel method (paper 001): conservative voxels, growing field, curved layers.
  { group: 'Voxel', key: 'voxel.width_mm', label: 'voxel width (mm, 0 = 0.8 × nozzle)', step: 0.05,
    testid: 'voxel-width', showIf: isVoxel, sendIf: isVoxel },
  { group: 'Voxel', key: 'voxel.strategy', label: 'growth strategy', type: 'select', testid: 'voxel-strategy',
    labels: { gcfa: 'GCFA', 'sp-gcfa': 'SP-GCFA', 'pg-gcfa': 'PG-GCFA', 'pg-sp-gcfa': 'PG-SP-GCFA' },
    showIf: isVoxel, sendIf: isVoxel },
  { group: 'Voxel', key: 'voxel.shadow', label: 'shadow prevention', type: 'select', testid: 'voxel-shadow',
    labels: { recursive: 'recursive (PCA split)', incremental: 'incremental (Dijkstra)' },
    showIf: (v) => isVoxel(v) && v['voxel.strategy'].includes('sp-'), sendIf: isVoxel },
  { group: 'Voxel', key: 'voxel.peel_step', label: 'peel step Δf', step: 0.5,
    testid: 'voxel-peel-step', showIf: (v) => isVoxel(v) && v['voxel.strategy'].startsWith('pg-'), sendIf: isVoxel },
  { group: 'Voxel', key: 'voxel.epsilon', label: 'hull tolerance ε (voxel widths, −1 = default)', step: 0.1,
    testid: 'voxel-epsilon', showIf: isVoxel, sendIf: isVoxel },
  { group: 'Voxel', key: 'voxel.layer_field', label: 'layers follow', type: 'select', testid: 'voxel-layer-field',
    labels: { distance: 'growth distance', steps: 'growth steps (G)', generations: 'generations from the platform' },
    showIf: isVoxel, sendIf: isVoxel },
  { group: 'Voxel', key: 'voxel.smooth', label: 'layer field smoothing (passes)', type: 'integer', step: 1,
    testid: 'voxel-smooth', showIf: isVoxel, sendIf: isVoxel },
  { group: 'Voxel', key: 'voxel.layer_mm', label: 'layer thickness (mm, 0 = voxel width)', step: 0.05,
    testid: 'voxel-layer-mm', showIf: isVoxel, sendIf: isVoxel },
  { group: 'Voxel', key: 'voxel.max_thickness_ratio', label: 'thickest layer (× layer; partial layers above; 0 = off)', step: 0.05,
    testid: 'voxel-max-thickness', showIf: isVoxel, sendIf: isVoxel },
  { group: 'Voxel', key: 'voxel.iso_step', label: 'iso step (field units, 0 = from the thickness)', step: 0.1,
    testid: 'voxel-iso-step', showIf: isVoxel, sendIf: isVoxel },
  { group: 'Voxel', key: 'voxel.max_tilt_deg', label: 'max nozzle tilt (°, 0 = machine)', step: 5,
    testid: 'voxel-max-tilt', showIf: isVoxel, sendIf: isVoxel },
  { group: 'Voxel', key: 'voxel.supports', label: 'supports under missed voxels', type: 'checkbox',
    testid: 'voxel-supports', showIf: isVoxel, sendIf: isVoxel },
  { group: 'Voxel', key: 'voxel.platform_radius_mm', label: 'platform radius (mm, 0 = footprint)', step: 1,
    testid: 'voxel-platform-radius', showIf: isVoxel, sendIf: isVoxel },
  { group: 'Voxel', key: 'voxel.max_voxels', label: 'max solid voxels', type: 'integer', step: 100000,
    testid: 'voxel-max-voxels', showIf: isVoxel, sendIf: isVoxel },
  // Iso-planar paths (paper 003): the drive-plane direction theta* of the best deposition rate.
  { group: 'Iso-planar', key: 'isoplanar.theta_deg', label: 'drive-plane direction θ (°, −1 = search θ*)', step: 1,
    testid: 'iso-theta', showIf: usesIsoplanar, sendIf: usesIsoplanar },
  { group: 'Iso-planar', key: 'isoplanar.directions', label: 'directions searched (over 180°)', type: 'integer', step: 1,
    testid: 'iso-directions', showIf: usesIsoplanar, sendIf: usesIsoplanar },
  { group: 'Iso-planar', key: 'isoplanar.chord_error_mm', label: 'chord error (mm, 0 = auto: min(0.5, layer/8))', step: 0.05,
    testid: 'iso-chord-error', showIf: usesIsoplanar, sendIf: usesIsoplanar },
  { group: 'Iso-planar', key: 'isoplanar.benchmark', label: 'benchmark over all directions', type: 'checkbox',
    testid: 'iso-benchmark', showIf: usesIsoplanar, sendIf: usesIsoplanar },
  { group: 'Iso-planar', key: 'surface.base_mm', label: 'support base under the surface (mm)', step: 0.5,
    testid: 'surface-base', showIf: isSurface, sendIf: isSurface },
  // The geodesic method (paper 002): tet mesh, heat-method geodesic field, iso-geodesic distance
  // surfaces (IGDS), skeleton tree and print sequence.
  { group: 'Geodesic', key: 'geodesic.interval_mm', label: 'IGDS interval (mm, 0 = layer height)', step: 0.05,
    testid: 'geodesic-interval', showIf: isGeodesic, sendIf: isGeodesic },
  { group: 'Geodesic', key: 'geodesic.tet_size_mm', label: 'tet size (mm, 0 = from the target count)', step: 0.1,
    testid: 'geodesic-tet-size', showIf: isGeodesic, sendIf: isGeodesic },
  { group: 'Geodesic', key: 'geodesic.target_tets', label: 'target tets', type: 'integer', step: 1000,
    testid: 'geodesic-target-tets', showIf: (v) => isGeodesic(v) && v['geodesic.tet_size_mm'] === 0, sendIf: isGeodesic },
  { group: 'Geodesic', key: 'geodesic.base_band_mm', label: 'base band (mm, the heat source: the part this close to the platform; 0 = a quarter interval)', step: 0.1,
    testid: 'geodesic-base-band', showIf: isGeodesic, sendIf: isGeodesic },
  { group: 'Geodesic', key: 'geodesic.max_thickness_ratio', label: 'thickest layer at the surface (× interval; 0 = uniform steps as in the paper)', step: 0.05,
    testid: 'geodesic-max-thickness', showIf: isGeodesic, sendIf: isGeodesic },
  { group: 'Geodesic', key: 'geodesic.align_passes', label: 'align merging fronts (smoothing passes; 0 = the paper\'s field)', type: 'integer', step: 1,
    testid: 'geodesic-align-passes', showIf: isGeodesic, sendIf: isGeodesic },
  { group: 'Geodesic', key: 'geodesic.align_retry_passes', label: 'where tool path is left out, slice again with (passes; 0 = no retry)', type: 'integer', step: 1,
    testid: 'geodesic-align-retry', showIf: isGeodesic, sendIf: isGeodesic },
  { group: 'Geodesic', key: 'geodesic.heat_time', label: 'heat time (× h², 1 = the paper)', step: 1,
    testid: 'geodesic-heat-time', showIf: isGeodesic, sendIf: isGeodesic },
  { group: 'Geodesic', key: 'geodesic.nozzle_angle_deg', label: 'nozzle angle (°, 0 = the machine\'s cone)', step: 1,
    testid: 'geodesic-nozzle-angle', showIf: isGeodesic, sendIf: isGeodesic },
  { group: 'Geodesic', key: 'geodesic.sequence', label: 'print sequence', type: 'select', testid: 'geodesic-sequence',
    labels: { a3: 'A3 (collision-aware, fewer air moves)', lpt: 'LPT (layer by layer)', dpt: 'DPT (branch by branch)' },
    showIf: isGeodesic, sendIf: isGeodesic },
  { group: 'Geodesic', key: 'geodesic.remesh', label: 'remesh and smooth the IGDS', type: 'checkbox',
    testid: 'geodesic-remesh', showIf: isGeodesic, sendIf: isGeodesic },
  // The multi-directional method (paper 000): clipping planes by a beam-guided search, each part
  // printed along its plane's normal.
  { group: 'Multi-directional', key: 'multidir.alpha_max_deg', label: 'self-supporting angle α_max (°)', step: 1,
    testid: 'multidir-alpha', showIf: isMultidir, sendIf: isMultidir },
  { group: 'Multi-directional', key: 'multidir.w', label: 'smallest part w (parts ≥ volume / w)', step: 1,
    testid: 'multidir-w', showIf: isMultidir, sendIf: isMultidir },
  { group: 'Multi-directional', key: 'multidir.scheme', label: 'search', type: 'select', testid: 'multidir-scheme',
    labels: { beam: 'beam-guided', greedy: 'greedy', constrained: 'constrained greedy' },
    showIf: isMultidir, sendIf: isMultidir },
  { group: 'Multi-directional', key: 'multidir.beam_width', label: 'beam width b', step: 1,
    testid: 'multidir-beam-width', showIf: (v) => isMultidir(v) && v['multidir.scheme'] === 'beam', sendIf: isMultidir },
  { group: 'Multi-directional', key: 'multidir.restarts', label: 'restarts (5 DOF beam, normals turned)', step: 1,
    testid: 'multidir-restarts', showIf: (v) => isMultidir(v) && v['multidir.scheme'] === 'beam', sendIf: isMultidir },
  { group: 'Multi-directional', key: 'multidir.perturbations', label: 'local search moves (beam, 0 = off)', step: 10,
    testid: 'multidir-perturbations', showIf: (v) => isMultidir(v) && v['multidir.scheme'] === 'beam', sendIf: isMultidir },
  { group: 'Multi-directional', key: 'multidir.dof', label: 'DOF mode', type: 'select', testid: 'multidir-dof',
    labels: { auto: 'auto (rotary4: 4 DOF, else 5 DOF)', '4dof': '4 DOF (one rotary axis)', '5dof': '5 DOF' },
    showIf: isMultidir, sendIf: isMultidir },
  { group: 'Multi-directional', key: 'multidir.interface_overlap', label: 'reach across later parts\' planes (× the safe depth, 0 = flush)', step: 0.1,
    testid: 'multidir-interface-overlap', showIf: isMultidir, sendIf: isMultidir },
  { group: 'Multi-directional', key: 'multidir.samples', label: 'candidate normals', step: 10,
    testid: 'multidir-samples', showIf: isMultidir, sendIf: isMultidir },
  { group: 'Multi-directional', key: 'multidir.axis_search', label: 'rotation axes searched (4 DOF, 0 = the machine\'s)', step: 1,
    testid: 'multidir-axis-search', showIf: (v) => isMultidir(v) && (v['multidir.dof'] === '4dof' || (v['multidir.dof'] === 'auto' && selectedMachineKind(v) === 'rotary4')),
    sendIf: isMultidir },
  // Supports (paper 000 Section V): projected through the multidir parts' subspaces, or along +Z
  // for a planar print (core/pipeline/settings.h SupportSettings).
  // Every method: planar and multidir project supports; voxel and geodesic add fins under beads
  // printed over air (auto: as the last resort, kept only when they make the program sound).
  { group: 'Supports', key: 'support', label: 'supports', type: 'select', testid: 'support-mode',
    labels: { auto: 'auto (multidir: projected; planar: where it overhangs; curved: fins when they make it sound)',
      none: 'none', projected: 'projected (curved: fins under whatever is over air)' } },
  { group: 'Supports', key: 'support.sampling_mm', label: 'overhang sampling R (mm, 0 = from the nozzle)', step: 0.5,
    testid: 'support-sampling', showIf: (v) => isPlanar(v) && v.support !== 'none', sendIf: isPlanar },
  { group: 'Supports', key: 'support.merge_angle_deg', label: 'tree branch angle (deg, 0 = straight columns)', step: 5,
    testid: 'support-merge', showIf: (v) => isPlanar(v) && v.support !== 'none', sendIf: isPlanar },
  { group: 'Supports', key: 'support.roof_layers', label: 'solid roof layers under an overhang', step: 1,
    testid: 'support-roof', showIf: (v) => isPlanar(v) && v.support !== 'none', sendIf: isPlanar },
  { group: 'Supports', key: 'support.gap_mm', label: 'gap to the part (mm)', step: 0.05,
    testid: 'support-gap', showIf: (v) => isPlanar(v) && v.support !== 'none', sendIf: isPlanar },
  { group: 'Speed', key: 'print_speed', label: 'print speed (mm/s)', step: 1 },
  { group: 'Speed', key: 'travel_speed', label: 'travel speed (mm/s)', step: 1 },
  { group: 'Speed', key: 'retract_length', label: 'retract (mm)', step: 0.1 },
  { group: 'Speed', key: 'travel_inside', label: 'travel inside the part', type: 'checkbox', showIf: isPlanar },
  { group: 'Speed', key: 'bridges', label: 'bridges', type: 'checkbox', showIf: isPlanar },
  { group: 'Speed', key: 'bridge_speed', label: 'bridge speed (mm/s)', step: 1, showIf: isPlanar },
  { group: 'Speed', key: 'fan_speed', label: 'part cooling fan (%)', step: 5, showIf: (v) => !isRobot(v) },
  { group: 'Speed', key: 'bridge_fan_speed', label: 'fan over bridges (%)', step: 5,
    showIf: (v) => isPlanar(v) && !isRobot(v) },
  { group: 'Placement', key: 'repair', label: 'repair the mesh', type: 'select', testid: 'repair',
    labels: { auto: 'auto (close holes, split non-manifold spots)', none: 'none (refuse such files)' } },
  { group: 'Placement', key: 'fit_mm', label: 'fit largest side (mm, 0 = off)', step: 1 },
  { group: 'Placement', key: 'scale', label: 'scale', step: 0.1 },
  { group: 'Placement', key: 'up', label: 'up axis of the file', type: 'select',
    labels: { z: '+Z', '-z': '−Z', y: '+Y', '-y': '−Y', x: '+X', '-x': '−X' } },
  { group: 'Placement', key: 'rotate_x_deg', label: 'rotate X (°)', step: 15 },
  { group: 'Placement', key: 'rotate_y_deg', label: 'rotate Y (°)', step: 15 },
  { group: 'Placement', key: 'rotate_z_deg', label: 'rotate Z (°)', step: 15 },
  { group: 'Placement', key: 'center', label: 'centre on the plate', type: 'checkbox' },
  { group: 'Motion', key: 'motion.free_rotation_samples', label: 'free-rotation samples (robot)', step: 1,
    showIf: isRobot },
  { group: 'Motion', key: 'motion.smooth_orientations', label: 'smooth orientations', type: 'checkbox' },
  { group: 'Motion', key: 'motion.filter_deg', label: 'orientation filter above (°)', step: 1 },
  { group: 'Motion', key: 'motion.axis_freedom_deg', label: 'axis freedom for motion (°, −1 = the method\'s)', step: 1,
    testid: 'axis-freedom', showIf: (v) => isVoxel(v) || isGeodesic(v) },
  { group: 'Motion', key: 'motion.chord_tolerance', label: 'chord tolerance (mm)', step: 0.001 },
];

/** The core types (settings_table.cpp) each page input type can edit. */
const CORE_TYPES = {
  number: ['number'],
  integer: ['integer', 'number'],
  select: ['choice'],
  checkbox: ['boolean'],
  direction: ['vector'],
  json: ['text'],
  text: ['text'],
};

/**
 * The settings fields the model and panel use: each of PAGE_FIELDS with what the core's settings
 * table says of it (coreSchema: slicer.settingsSchema(), [{key, type, default (text), min, max,
 * unit, help, choices}]). A field gets value (the core's default: a number, a boolean or text),
 * min and max (numbers), options [{label, value}] (selects: the core's choices in the order of the
 * page's labels, then any the page has no label for, labelled by their value, less the page
 * field's `omit` list), help and unit.
 * Throws an Error naming the key when a page field is not in the core's table or does not fit it
 * (type, a labelled choice the core does not accept, a default the input cannot hold): the page
 * and the core have drifted apart.
 */
export function settingsFields(coreSchema) {
  const table = new Map(coreSchema.map((s) => [s.key, s]));
  return PAGE_FIELDS.map(({ core: coreKey = null, labels = null, omit = [], ...page }) => {
    const fail = (why) => { throw new Error(`settings field '${page.key}': ${why}`); };
    const core = table.get(coreKey || page.key);
    if (!core) fail(`${coreKey ? `its core key '${coreKey}' is` : 'it is'} not in the core's settings table`);
    // Without a page type the core's number or integer is the input's.
    const type = page.type || core.type;
    if (!(CORE_TYPES[type] || []).includes(core.type)) {
      fail(page.type ? `a ${type} input cannot edit the core's ${core.type} setting` : `the core's ${core.type} setting needs a page input type`);
    }
    const field = { ...page, type, help: core.help, unit: core.unit };
    if (type === 'number' || type === 'integer') {
      field.value = Number(core.default);
      if (!Number.isFinite(field.value)) fail(`default '${core.default}' is not a number`);
      if (type === 'integer' && !Number.isInteger(field.value)) fail(`default '${core.default}' is not a whole number`);
      field.min = core.min;
      field.max = core.max;
    } else if (type === 'select') {
      const choices = core.choices || [];
      const order = Object.keys(labels || {});
      for (const value of order) if (!choices.includes(value)) fail(`the core does not accept the labelled choice '${value}'`);
      const offered = choices.filter((c) => !omit.includes(c));
      field.options = [...order, ...offered.filter((c) => !order.includes(c))].map((value) => ({ label: labels?.[value] ?? value, value }));
      field.value = core.default;
    } else if (type === 'checkbox') {
      field.value = core.default === 'true';
    } else if (type === 'direction') {
      field.value = parseDirection(core.default) ?? fail(`default '${core.default}' is not a direction`);
    } else {
      field.value = core.default;
    }
    return field;
  });
}

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
