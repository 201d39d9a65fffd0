// SPDX-License-Identifier: MIT
// App wiring: file input and drag-and-drop -> slicer.loadMesh; Slice/Cancel -> slicer.slice with
// progress (a multidir search's levels as the decompose stage's text and a live J_G chart);
// result -> viewer (model + tool-path preview), report figures and program download (G-code,
// robot CSV or URScript, by the result's programExtension); the machine panel (built-in machine,
// flavour, a user's profile file checked by the core); the machine animation (MachineView: the
// articulated machine moving the part, driven by preview.machine).
// All heavy work runs in the engine's worker; the main thread only moves typed arrays around.
// The page's state is mirrored on <body data-state> (starting, loading, ready, slicing, done,
// error, cancelled) and <body data-slice-count>, which the end-to-end tests wait on.
import { svgElement } from './panel-dom.js';
import { describeList, figure, formatLength, formatMm, formatSeconds, withUnit } from './format.js';
import { Viewer } from './viewer.js';
import { ToolpathPreview, FEATURES, featureCss } from './preview.js';
import {
  SettingsModel, History, SetSettingCommand, createSettingsPanel, selectedMachineKind,
} from './settings-panel.js';
import { isPlacementKey } from './placement.js';
import { PROGRAM_KINDS, programExtension, programFileName } from './program-file.js';
import { MachineView } from './machine-view.js';
import { machineAxisNames } from './machine-kinematics.js';
import { VoxelView, hasVoxelBuffers } from './methods/voxel-view.js';
import {
  STAGE_WEIGHTS, histogramGeometry, layerColor, overallProgress, voxelDoneSummary, voxelSummaryRows,
} from './methods/voxel-data.js';
import { CURVE_COLORS, comparisonRows, foldTheta, sideStepText } from './methods/isoplanar-data.js';
import { drawPolarPlot, fillCompareTable, fillIsoFigures, plotThetaAt } from './methods/isoplanar-panel.js';
import { GeodesicView } from './methods/geodesic-view.js';
import { geodesicDoneSummary, hasGeodesicBuffers, rampCss } from './methods/geodesic-data.js';
import { drawOverhangChart, fillGeoFigures, fillTraversalTable, setChartLayer } from './methods/geodesic-panel.js';
import { MultidirView } from './methods/multidir-view.js';
import {
  areaFigure, hasMultidirBuffers, liveJgLevels, multidirDoneSummary, searchLevelText, supportText,
} from './methods/multidir-data.js';
import { drawJgChart, drawJgLevels, fillMultidirFigures, fillPartsTable } from './methods/multidir-panel.js';

const DEMO_URL = '/models/demo-overhang.stl';
const DEMO_NAME = 'demo-overhang.stl';
/** Bundled demo models (web/models, made by scripts/make-demo-model.mjs) for the model menu. */
const DEMOS = {
  overhang: { url: DEMO_URL, name: DEMO_NAME },
  // An open saddle z = (x^2 - y^2) / R: the surface method's iso-planar paths (paper 003, S1).
  // The surface method needs tilt axes: a 3- or 4-axis machine is swapped for the UR5 arm.
  saddle: { url: '/models/demo-saddle.obj', name: 'demo-saddle.obj', settings: { method: 'surface' }, tilt: 'robot6-ur5' },
  // A trunk forking into three tilted branches (scripts/make-demo-tree.mjs): the geodesic
  // method's curved layers, skeleton tree and print sequences (paper 002). At a 45° nozzle angle
  // DPT collides while A3 stays collision-free with a tenth of LPT's retractions (README.md).
  tree: {
    url: '/models/demo-tree.obj', name: 'demo-tree.obj', tilt: 'table5',
    settings: { method: 'geodesic', nozzle: 0.8, 'geodesic.interval_mm': 0.8, 'geodesic.nozzle_angle_deg': 45, 'geodesic.sequence': 'a3' },
  },
};
const FILAMENT_AREA_MM2 = Math.PI * (1.75 / 2) ** 2;
const PLA_G_PER_MM3 = 1.24e-3;

const $ = (id) => document.querySelector(`[data-testid="${id}"]`);

const app = {
  slicer: null,
  viewer: null,
  preview: null,
  voxelView: null,   // VoxelView of the result's curved layers, missed voxels and nozzle axes
  geodesicView: null, // GeodesicView of the result's distance field, skeleton tree and air moves
  multidirView: null, // MultidirView of the result's parts, print directions and risky faces
  model: new SettingsModel(),
  history: new History(),
  mesh: null,        // {name, meshId, info} of the loaded mesh
  result: null,      // last successful slice result
  busy: null,        // 'loading' | 'placing' | 'slicing' | 'showing' | null
  abort: null,       // AbortController of the running slice
  placementDirty: false,
  sliceCount: 0,
  progress: newProgress('planar'),
  machineFiles: new Map(), // machine_json text -> file name it was loaded from (undo may bring any back)
  machineView: null, // MachineView of app.replay or app.result while the machine toggle is on
  replay: null,      // {name, profile, preview} of a replayed program file (shown instead of the result)
  machinePlay: 0,    // requestAnimationFrame id while playing
  resultSettings: null, // the slice settings app.result was made with (the compare run reuses them)
  compare: null,     // {theta, result} of the iso-planar comparison run (app.result stays the first)
  shownRun: 0,       // 0: app.result's paths are drawn, 1: app.compare's
  compareCount: 0,
};

/** Run fn as one measured step (performance.measure 'omnislice:<name>'), for the tests' long-task check. */
function timed(name, fn) {
  const t0 = performance.now();
  try {
    return fn();
  } finally {
    performance.measure(`omnislice:${name}`, { start: t0, end: performance.now() });
  }
}

function setState(state) {
  document.body.dataset.state = state;
}

function nextFrame() {
  return new Promise((resolve) => requestAnimationFrame(() => setTimeout(resolve, 0)));
}

// ---- errors and progress -----------------------------------------------------------------------

function showError(err) {
  const el = $('error-message');
  const code = (err && err.code) || 'internal';
  const message = (err && err.message) || String(err);
  el.textContent = `${code}: ${message}`;
  el.dataset.code = code;
  el.classList.toggle('notice', code === 'cancelled');
  el.hidden = false;
}

function clearError() {
  const el = $('error-message');
  el.hidden = true;
  el.textContent = '';
  delete el.dataset.code;
}

function setProgressText(text, fraction) {
  $('progress-text').textContent = text;
  const bar = $('progress');
  // The bar carries the stage text too (accessible name and fallback content).
  bar.textContent = text;
  bar.setAttribute('aria-valuetext', text);
  if (fraction !== undefined) bar.value = fraction;
}

/**
 * Progress state of one slice: the method's stage weights, every stage seen with its times, and
 * the search levels of a multidir decomposition as they come.
 */
function newProgress(method) {
  return {
    stage: '', fraction: 0, overall: 0, pending: false,
    weights: STAGE_WEIGHTS[method] || STAGE_WEIGHTS.planar,
    stages: new Map(),  // stage -> {fraction, start, end (performance.now() ms), detail}, in arrival order
    levels: [],         // progress.search of every search-level event, in arrival order
    levelsDrawn: 0,     // levels shown by the live J_G chart
    liveDraws: [],      // the live chart's values at each drawing (for the tests)
  };
}

/**
 * Progress callback: keep the latest value, paint once per frame. A search-level event (stage
 * 'decompose', progress.search) becomes its stage's detail text and a point of the live chart.
 */
function onProgress({ stage, fraction, search }) {
  const p = app.progress;
  p.stage = stage;
  p.fraction = Math.min(Math.max(Number(fraction) || 0, 0), 1);
  const overall = overallProgress(p.weights, stage, p.fraction);
  if (overall !== null) p.overall = Math.max(p.overall, overall);
  const now = performance.now();
  let entry = p.stages.get(stage);
  if (!entry) {
    // A new stage ends the previous ones.
    for (const e of p.stages.values()) e.fraction = 1;
    entry = { fraction: 0, start: now, end: now };
    p.stages.set(stage, entry);
  }
  entry.fraction = Math.max(entry.fraction, p.fraction);
  entry.end = now;
  if (search) {
    p.levels.push(search);
    entry.detail = searchLevelText(search);
  }
  if (p.pending) return;
  p.pending = true;
  requestAnimationFrame(() => {
    p.pending = false;
    if (app.busy && app.progress === p) {
      const detail = p.stages.get(p.stage)?.detail;
      setProgressText(`${p.stage} ${Math.round(p.fraction * 100)}%${detail ? ` — ${detail}` : ''}`, p.overall);
      showStages();
      // The chosen sequence's levels come in a burst at the end of decompose: drawn once the
      // next stage starts, not one by one (the chart would shrink to its first point).
      const chosenComing = p.stage === 'decompose' && p.levels.at(-1)?.line === 'chosen';
      if (p.levels.length !== p.levelsDrawn && !chosenComing) showLiveSearch(p);
    }
  });
}

/** The stage list under the progress bar: name, percentage and time of every stage seen. */
function showStages({ finished = false } = {}) {
  const p = app.progress;
  const list = $('stage-list');
  const items = [];
  const entries = [...p.stages];
  let k = 0;
  for (const [stage, e] of entries) {
    const last = k++ === entries.length - 1;
    // A stage lasts from its first report to the next stage's first report (or its own last).
    const end = last ? e.end : entries[k][1].start;
    const li = document.createElement('li');
    li.dataset.stage = stage;
    const done = finished || !last || e.fraction >= 1;
    li.className = done ? 'done' : 'running';
    const name = document.createElement('span');
    name.textContent = stage;
    const pct = document.createElement('span');
    pct.className = 'pct';
    pct.textContent = `${Math.round((done ? 1 : e.fraction) * 100)}%`;
    const ms = document.createElement('span');
    ms.className = 'ms';
    const dt = end - e.start;
    ms.textContent = dt >= 1000 ? `${(dt / 1000).toFixed(1)} s` : `${Math.round(dt)} ms`;
    li.append(name, pct, ms);
    if (e.detail) {
      const detail = document.createElement('span');
      detail.className = 'detail';
      detail.textContent = e.detail;
      li.append(detail);
    }
    items.push(li);
  }
  list.replaceChildren(...items);
}

// ---- figures --------------------------------------------------------------------------------------

/** 'x,y,z' (or [x, y, z]) -> three finite numbers, else null. */
function parseVector(value) {
  const parts = Array.isArray(value) ? value.map(Number) : typeof value === 'string' ? value.split(',').map(Number) : [];
  return parts.length === 3 && parts.every(Number.isFinite) ? parts : null;
}

function bboxSize(bbox) {
  if (!bbox) return null;
  const min = bbox.min || bbox[0];
  const max = bbox.max || bbox[1];
  if (!Array.isArray(min) || !Array.isArray(max)) return null;
  return max.map((x, i) => x - min[i]);
}

function showInfo(name, info) {
  $('model-name').textContent = name;
  $('info-faces').textContent = info && info.faces !== undefined ? Number(info.faces).toLocaleString('en') : '—';
  $('info-closed').textContent = info && info.closed !== undefined ? (info.closed ? 'yes' : 'no') : '—';
  // The placed part's box (part frame), else the file's.
  const size = bboxSize(info && (info.placed_bbox || info.bbox));
  $('info-size').textContent = size ? size.map((x) => x.toFixed(1)).join(' × ') : '—';
  const repairs = describeList(info && info.repairs);
  $('info-repairs').textContent = repairs.length ? repairs.join(', ') : 'none';
  const notes = $('info-warnings');
  notes.replaceChildren();
  for (const [kind, list] of [['error', info && info.errors], ['warning', info && info.warnings]]) {
    for (const text of describeList(list)) {
      const li = document.createElement('li');
      li.className = kind;
      li.textContent = text;
      notes.append(li);
    }
  }
}

function showReport(report) {
  const r = report || {};
  $('report-layers').textContent = r.layers !== undefined ? String(r.layers) : '—';
  $('report-time').textContent = formatSeconds(r.estimated_time_s);
  if (Number.isFinite(r.extrusion_mm)) {
    const grams = r.extrusion_mm * FILAMENT_AREA_MM2 * PLA_G_PER_MM3;
    $('report-filament').textContent = `${formatLength(r.extrusion_mm)} (${grams.toFixed(1)} g PLA)`;
  } else {
    $('report-filament').textContent = '—';
  }
  $('report-path').textContent = formatLength(r.path_mm);
  // Projected supports: the planar report's `support`, or the multidir report's `supports`.
  $('report-supports').textContent = supportText(r.support || (r.multidir && r.multidir.supports));
  const t = r.timings_ms && typeof r.timings_ms === 'object' ? r.timings_ms : null;
  const total = t && (Number.isFinite(t.total) ? t.total
    : Object.values(t).filter(Number.isFinite).reduce((a, b) => a + b, 0));
  $('report-took').textContent = t ? `${(total / 1000).toFixed(2)} s in the engine` : '—';
  $('report-machine').textContent = r.machine ? `${r.machine}${r.machine_kind && r.machine_kind !== r.machine ? ` (${r.machine_kind})` : ''}` : '—';
  $('report-program').textContent = r.program_format || r.program_extension || '—';
  // What the user should know about this result (e.g. tool path left out): code and message.
  const notes = $('report-warnings');
  notes.replaceChildren();
  for (const w of Array.isArray(r.warnings) ? r.warnings : []) {
    const li = document.createElement('li');
    li.className = 'warning';
    li.dataset.code = w && w.code ? String(w.code) : '';
    li.textContent = describeList([w])[0];
    notes.append(li);
  }
  const motion = r.motion && typeof r.motion === 'object' ? r.motion : null;
  $('report-motion').hidden = !motion;
  showVoxelReport(r.voxel && typeof r.voxel === 'object' ? r.voxel : null);
  showIsoReport(r.isoplanar && typeof r.isoplanar === 'object' ? r.isoplanar : null);
  showGeoReport(r.geodesic && typeof r.geodesic === 'object' ? r.geodesic : null);
  showMultidirReport(r.multidir && typeof r.multidir === 'object' ? r.multidir : null);
  // Angular figures are radians for a robot's joints, degrees for the A, B, C axes.
  const unit = r.machine_kind === 'robot6' ? ' rad' : '°';
  for (const key of ['samples', 'subdivisions', 'filtered_orientations', 'feed_limited_moves', 'safe_rotations',
    'max_joint_step', 'pose_cost', 'min_singularity']) {
    let text = '—';
    if (motion && key === 'pose_cost' && Number.isFinite(motion.pose_cost)) {
      text = `${figure(motion.pose_cost)}${unit}${Number.isFinite(motion.greedy_pose_cost) ? ` (${figure(motion.greedy_pose_cost)}${unit})` : ''}`;
    } else if (motion && key === 'max_joint_step' && Number.isFinite(motion.max_joint_step)) {
      text = `${figure(motion.max_joint_step)}${unit}`;
      if (r.machine_kind === 'robot6') text += ` (${figure((motion.max_joint_step * 180) / Math.PI)}°)`;
    } else if (motion && motion[key] !== undefined && motion[key] !== null) {
      text = figure(motion[key]);
    }
    $(`motion-${key}`).textContent = text;
  }
}

/** The voxel method's figures, histogram and summary (hidden for other methods). */
function showVoxelReport(v) {
  const section = $('voxel-report');
  section.hidden = !v;
  const dl = $('voxel-figures');
  dl.replaceChildren();
  renderHistogram(v && v.thickness);
  if (!v) return;
  for (const [key, label, text] of voxelSummaryRows(v)) {
    const dt = document.createElement('dt');
    dt.textContent = label;
    const dd = document.createElement('dd');
    dd.dataset.testid = `voxel-${key}`;
    dd.textContent = text;
    dl.append(dt, dd);
  }
}

/**
 * Draw report.voxel.thickness.histogram (counts of thickness minus the mean, mm) into the SVG:
 * bars, x ticks in mm, a line at deviation 0 (the mean) and dotted lines at ± one std.
 */
function renderHistogram(thickness) {
  const svg = $('thickness-histogram');
  const stats = $('thickness-stats');
  svg.replaceChildren();
  delete svg.dataset.bars;
  delete svg.dataset.total;
  const hist = thickness && thickness.histogram;
  if (!hist) {
    stats.textContent = '—';
    return;
  }
  let geo;
  try {
    geo = histogramGeometry(hist, { width: 260, height: 110 });
  } catch (err) {
    stats.textContent = `(${err.message})`;
    return;
  }
  for (const b of geo.bars) {
    const rect = svgElement('rect', {
      class: b.count > 0 ? 'bar' : 'bar empty', x: b.x + 0.5, y: b.count > 0 ? b.y : geo.plot.y + geo.plot.height - 1,
      width: Math.max(b.width - 1, 0.5), height: b.count > 0 ? b.height : 1,
    });
    rect.append(svgElement('title', {}, `${formatMm(b.from)}–${formatMm(b.to)} mm: ${b.count}`));
    svg.append(rect);
  }
  const base = geo.plot.y + geo.plot.height;
  svg.append(svgElement('line', { class: 'axis', x1: geo.plot.x, y1: base, x2: geo.plot.x + geo.plot.width, y2: base }));
  // Labels near the ends are anchored inside the plot so they are not clipped.
  for (const t of geo.ticks) {
    const anchor = t.x - geo.plot.x < 14 ? 'start' : geo.plot.x + geo.plot.width - t.x < 14 ? 'end' : 'middle';
    svg.append(svgElement('line', { class: 'axis', x1: t.x, y1: base, x2: t.x, y2: base + 3 }));
    svg.append(svgElement('text', { class: 'tick', x: t.x, y: base + 12, 'text-anchor': anchor }, t.label));
  }
  const n = geo.bars.length;
  const std = Number(thickness.std_mm);
  if (n) {
    const lo = geo.bars[0].from;
    const hi = geo.bars[n - 1].to;
    const marks = [[0, 'mean']];
    if (std > 0) marks.push([-std, 'std'], [std, 'std']);
    for (const [d, cls] of marks) {
      if (d < lo || d > hi) continue;
      const x = geo.plot.x + ((d - lo) / (hi - lo)) * geo.plot.width;
      svg.append(svgElement('line', { class: cls, x1: x, y1: geo.plot.y, x2: x, y2: base }));
    }
  }
  svg.dataset.bars = String(n);
  svg.dataset.total = String(geo.total);
  const mm = (x) => withUnit(Number(x), 'mm', formatMm);
  stats.textContent = `mean ${mm(thickness.mean_mm)}, std ${mm(thickness.std_mm)}, max deviation ${mm(thickness.max_deviation_mm)}`
    + (Number.isFinite(thickness.samples) ? ` (${thickness.samples.toLocaleString('en')} samples)` : '');
}

// ---- iso-planar paths (paper 003) ------------------------------------------------------------

/** The iso-planar figures, polar plot and comparison (hidden without report.isoplanar). */
function showIsoReport(iso) {
  $('iso-report').hidden = !iso;
  // A new result proposes the direction square to theta* for the comparison.
  if (iso && !app.compare && Number.isFinite(iso.theta_deg)) $('iso-compare-theta').value = String(foldTheta(iso.theta_deg + 90));
  fillIsoFigures($('iso-figures'), iso);
  renderPolar(iso);
  renderCompareTable();
  $('iso-side-step').textContent = sideStepText(iso);
  $('iso-curve-swatch-odd').style.background = `rgb(${CURVE_COLORS[0].join(',')})`;
  $('iso-curve-swatch-even').style.background = `rgb(${CURVE_COLORS[1].join(',')})`;
}

/** The iso-planar report of the first run (app.result), or null. */
function firstIso() {
  const r = app.result && app.result.report;
  return r && r.isoplanar && typeof r.isoplanar === 'object' ? r.isoplanar : null;
}

/** The direction the compare input holds, folded into [0, 180), or null when it is not a number. */
function compareTheta() {
  const text = $('iso-compare-theta').value.trim();
  const x = Number(text);
  return text !== '' && Number.isFinite(x) ? foldTheta(x) : null;
}

/**
 * The polar plot of the first run, with the compared direction: the compared run's (and the
 * input's as the next candidate when it differs), else the input's.
 */
function renderPolar(iso) {
  const input = compareTheta();
  const options = app.compare
    ? { compareTheta: app.compare.theta, candidateTheta: input !== null && input !== app.compare.theta ? input : null }
    : { compareTheta: input };
  const star = drawPolarPlot($('iso-polar'), iso, options);
  const ok = star && !star.error;
  $('iso-theta-star').textContent = ok ? `${figure(star.theta)}°${iso.forced ? ' (forced)' : ''}` : star ? `(${star.error})` : '—';
  $('iso-ve-star').textContent = ok && Number.isFinite(star.value) ? `${figure(star.value)} mm³/s` : '—';
}

/** Click on the polar plot: the direction there goes to the compare input (and is marked). */
function onPolarClick(event) {
  const theta = plotThetaAt($('iso-polar'), event.clientX, event.clientY);
  if (theta === null) return;
  $('iso-compare-theta').value = String(theta);
  renderPolar(firstIso());
}

/** The iso-planar runs for the comparison table: the first (app.result), the compared one. */
function compareRuns() {
  const iso = firstIso();
  if (!iso) return [];
  const runs = [{ label: iso.forced ? 'first run (forced θ)' : 'first run (θ*)', report: app.result.report }];
  if (app.compare) runs.push({ label: 'compared run', report: app.compare.result.report });
  return runs;
}

/** The comparison table: the first run, the compared run (when there is one), the benchmark means. */
function renderCompareTable() {
  fillCompareTable($('iso-compare-table').querySelector('tbody'), compareRuns());
}

/**
 * Slice again with the first run's settings and isoplanar.theta_deg forced to the compare input's
 * direction; the first result stays (report, download, paths); the table shows both runs side by
 * side. A failed comparison leaves the first result as it was.
 */
async function runCompare() {
  if (!app.slicer || !app.mesh || app.busy || !firstIso()) return;
  const theta = compareTheta();
  if (theta === null) {
    showError({ code: 'invalid_option', message: 'compare: give a direction θ in degrees, 0..180' });
    return;
  }
  app.busy = 'slicing';
  app.abort = new AbortController();
  app.progress = newProgress(app.model.get('method'));
  $('stage-list').replaceChildren();
  clearError();
  setState('slicing');
  setProgressText(`comparing θ = ${figure(theta)}°`, 0);
  updateButtons();
  const started = performance.now();
  try {
    // The first run's settings (later edits in the panel do not leak into the comparison).
    const settings = { ...(app.resultSettings || app.model.toSliceSettings()), 'isoplanar.theta_deg': theta };
    const result = await app.slicer.slice(app.mesh.meshId, settings, { onProgress, signal: app.abort.signal });
    app.compare = { theta, result };
    if (app.shownRun === 1) await showRun(1);
    renderPolar(firstIso());
    renderCompareTable();
    $('iso-show-run').disabled = false;
    app.compareCount += 1;
    document.body.dataset.compareCount = String(app.compareCount);
    setProgressText(`compared θ = ${figure(theta)}° in ${((performance.now() - started) / 1000).toFixed(2)} s`, 1);
    showStages({ finished: true });
    setState('done');
  } catch (err) {
    showError(err);
    setProgressText(err && err.code === 'cancelled' ? 'cancelled' : 'compare failed', 0);
    setState(err && err.code === 'cancelled' ? 'cancelled' : 'error');
  } finally {
    app.busy = null;
    app.abort = null;
    updateButtons();
  }
}

/** Draw the paths of run k (0: the first result, 1: the compared run). */
async function showRun(k) {
  const run = k === 1 && app.compare ? app.compare.result : app.result;
  app.shownRun = run === app.result ? 0 : 1;
  $('iso-show-run').value = String(app.shownRun);
  if (!run) return;
  await setPreview(run);
}

/** Forget the comparison run (a new slice or model). */
function clearCompare() {
  app.compare = null;
  app.shownRun = 0;
  const select = $('iso-show-run');
  select.value = '0';
  select.disabled = true;
}

function clearReport() {
  clearCompare();
  showReport(null);
  app.result = null;
  app.replay = null;
  $('download-program').disabled = true;
  setDownloadLabel('gcode');
  closeMachineView();
}

function setDownloadLabel(extension) {
  const kind = PROGRAM_KINDS[programExtension(extension)];
  $('download-program').textContent = `Download ${kind.label}`;
}

// ---- geodesic method (paper 002) ----------------------------------------------------------------

/** The geodesic report of the shown result, or null. */
function firstGeo() {
  const r = app.result && app.result.report;
  return r && r.geodesic && typeof r.geodesic === 'object' ? r.geodesic : null;
}

/** The geodesic figures, overhang chart and traversal table (hidden without report.geodesic). */
function showGeoReport(g) {
  $('geo-report').hidden = !g;
  fillGeoFigures($('geo-figures'), g);
  renderTraversals(g);
  const chart = drawOverhangChart($('geo-overhang-chart'), g, { layer: g ? Number($('layer-slider').value) : null });
  const stats = $('geo-chart-stats');
  if (!chart) stats.textContent = '—';
  else if (chart.error) stats.textContent = `(${chart.error})`;
  else stats.textContent = `${chart.layers} layers, largest ${figure(chart.maxValue)}°, ${chart.over} above 45°`;
}

function renderTraversals(g) {
  fillTraversalTable($('geo-traversal-table').querySelector('tbody'), g, { onChoose: (name) => chooseSequence(name), disabled: !!app.busy });
}

/** Slice again with another print sequence (an undoable settings edit, then a slice). */
async function chooseSequence(name) {
  if (app.busy || !app.mesh) return;
  if (app.model.get('geodesic.sequence') !== name) app.history.execute(new SetSettingCommand(app.model, 'geodesic.sequence', name));
  await slice();
}

/** The geodesic bar follows app.geodesicView (hidden without one). */
function setupGeoBar() {
  const v = app.geodesicView;
  $('geo-bar').hidden = !v;
  // The voxel bar's missed and support cells mean nothing for the geodesic method.
  for (const id of ['show-missed', 'show-support']) $(id).closest('label').hidden = !!v;
  const slider = $('geo-step-slider');
  const n = v ? v.nodeCount : 0;
  slider.max = String(Math.max(n - 1, 0));
  slider.value = slider.max;
  slider.disabled = n === 0;
  $('field-ramp').style.background = rampCss();
  if (v) {
    v.setVisible('field', $('show-field').checked);
    v.setVisible('tree', $('show-tree').checked);
    v.setVisible('air', $('show-air').checked);
  }
  applyGeoStep();
}

/** Show the tree as printed up to the step slider's position; the texts follow. */
function applyGeoStep() {
  const v = app.geodesicView;
  const slider = $('geo-step-slider');
  if (!v) {
    $('geo-step-text').textContent = '—';
    $('field-range').textContent = '—';
    $('air-count').textContent = '0';
    return;
  }
  v.setStep(Number(slider.value));
  showGeoStats();
}

function showGeoStats() {
  const v = app.geodesicView;
  if (!v) return;
  const s = v.stats();
  const c = s.current;
  $('geo-step-text').textContent = s.nodes
    ? `${s.step + 1} of ${s.nodes}${c ? ` (layer ${c.layer + 1})` : ''}` : 'no tree';
  $('field-range').textContent = `${formatMm(s.fieldMin)}–${formatMm(s.fieldMax)} mm`;
  $('air-count').textContent = s.airDrawn === s.airMoves ? String(s.airMoves) : `${s.airDrawn} / ${s.airMoves}`;
  const slider = $('geo-step-slider');
  slider.dataset.fieldDrawn = String(s.fieldDrawn);
  slider.dataset.nodesDrawn = String(s.nodesDrawn);
  slider.dataset.airDrawn = String(s.airDrawn);
  app.viewer && app.viewer.requestRender();
}

function setGeoLayerVisible(kind, visible) {
  if (!app.geodesicView) return;
  app.geodesicView.setVisible(kind, visible);
  showGeoStats();
}

// ---- multi-directional method (paper 000) -------------------------------------------------------

/** The multidir figures, parts table and J_G chart (hidden without report.multidir). */
function showMultidirReport(m) {
  $('md-report').hidden = !m;
  fillMultidirFigures($('md-figures'), m);
  fillPartsTable($('md-parts-table').querySelector('tbody'), m);
  const chart = drawJgChart($('md-jg-chart'), m);
  const stats = $('md-chart-stats');
  if (!chart) stats.textContent = '—';
  else if (chart.error) stats.textContent = `(${chart.error})`;
  else stats.textContent = `${chart.points} levels, ${areaFigure(chart.first)} → ${areaFigure(chart.last)} mm²`;
}

/**
 * The J_G chart of a running decomposition, from its search levels so far (the report's chart
 * replaces it when the result comes). Its first drawing in a slice shows the multidir report
 * group and clears the previous result's figures and parts table.
 */
function showLiveSearch(p) {
  p.levelsDrawn = p.levels.length;
  const values = liveJgLevels(p.levels);
  if (values.length === 0) return;
  if (p.liveDraws.length === 0) {
    $('md-report').hidden = false;
    fillMultidirFigures($('md-figures'), null);
    fillPartsTable($('md-parts-table').querySelector('tbody'), null);
  }
  p.liveDraws.push(values);
  const chart = drawJgLevels($('md-jg-chart'), values, { live: true });
  $('md-chart-stats').textContent = chart && !chart.error
    ? `searching: ${chart.points} levels, ${areaFigure(chart.first)} → ${areaFigure(chart.last)} mm²` : '—';
}

/** The multidir bar follows app.multidirView (hidden without one). */
function setupMultidirBar() {
  const v = app.multidirView;
  $('md-bar').hidden = !v;
  const slider = $('md-order-slider');
  const n = v ? v.partCount : 0;
  slider.max = String(Math.max(n - 1, 0));
  slider.value = slider.max;
  slider.disabled = n === 0;
  if (v) {
    v.setVisible('parts', $('show-parts').checked);
    v.setVisible('arrows', $('show-arrows').checked);
    v.setRisky($('md-risky').value);
  }
  applyMultidirOrder();
}

/** Show the parts printed up to the order slider's position; the texts follow. */
function applyMultidirOrder() {
  const v = app.multidirView;
  if (!v) {
    $('md-order-text').textContent = '—';
    $('md-risky-text').textContent = '—';
    return;
  }
  v.setOrder(Number($('md-order-slider').value));
  showMultidirStats();
}

function showMultidirStats() {
  const v = app.multidirView;
  if (!v) return;
  const s = v.stats();
  $('md-order-text').textContent = s.parts ? `${s.order + 1} of ${s.parts}` : 'no parts';
  $('md-risky-text').textContent = s.risky === 'none' ? ''
    : `${s.riskyTriangles[s.risky]} faces, ${areaFigure(s.riskyAreaMm2[s.risky])} mm²`;
  const slider = $('md-order-slider');
  slider.dataset.partsShown = String(s.partsShown);
  slider.dataset.trianglesDrawn = String(s.trianglesDrawn);
  slider.dataset.arrowsDrawn = String(s.arrowsDrawn);
  app.viewer && app.viewer.requestRender();
}

function setMultidirOption(apply) {
  if (!app.multidirView) return;
  apply(app.multidirView);
  showMultidirStats();
}

// ---- layer range ------------------------------------------------------------------------------

/** The layer sliders span layerCount layers, showing from `first` (default 0) to the last. */
function setupLayerSliders(layerCount, first = 0) {
  const lo = $('layer-min-slider');
  const hi = $('layer-slider');
  const last = Math.max(layerCount - 1, 0);
  for (const s of [lo, hi]) {
    s.max = String(last);
    s.disabled = layerCount === 0;
  }
  lo.value = String(Math.min(Math.max(first, 0), last));
  hi.value = String(last);
  applyLayerRange();
}

function applyLayerRange(changed) {
  const lo = $('layer-min-slider');
  const hi = $('layer-slider');
  let a = Number(lo.value);
  let b = Number(hi.value);
  if (a > b) {
    if (changed === lo) b = a;
    else a = b;
    lo.value = String(a);
    hi.value = String(b);
  }
  const n = app.preview ? app.preview.layerCount : 0;
  $('layer-text').textContent = n ? `${a + 1}–${b + 1} of ${n}` : '—';
  if (app.preview) {
    app.preview.setLayerRange(a, b);
    app.viewer && app.viewer.requestRender();
  }
  if (app.voxelView) app.voxelView.setGlyphLayerRange(a, b);
  if (app.geodesicView) {
    // At the slider's top the whole field and tree show, also the layers above the last printed one.
    app.geodesicView.setLayerRange(a, b >= Number(hi.max) ? Number.MAX_SAFE_INTEGER : b);
    showGeoStats();
  }
  setChartLayer($('geo-overhang-chart'), app.preview ? b : null);
}

/** The surface slider and the voxel bar follow app.voxelView (hidden without one). */
function setupVoxelBar() {
  const v = app.voxelView;
  $('voxel-bar').hidden = !v;
  const slider = $('layer-surface-slider');
  const n = v ? v.surfaceLayerCount : 0;
  slider.max = String(Math.max(n - 1, 0));
  slider.value = slider.max;
  slider.disabled = n === 0;
  const missed = $('missed-count');
  const reported = app.result && app.result.report && app.result.report.voxel ? app.result.report.voxel.missed_voxels : undefined;
  const count = Number.isFinite(reported) ? reported : v ? v.missedCount : 0;
  missed.textContent = count.toLocaleString('en');
  missed.classList.toggle('alert', count > 0);
  $('support-count').textContent = (v ? v.supportCount : 0).toLocaleString('en');
  // The layer colour ramp (the colours of layers spread over the count; neighbours alternate in lightness).
  const ramp = $('layer-ramp');
  const L = v ? v.surfaceLayerCount : 0;
  const stops = [];
  for (let k = 0; k < Math.min(L, 12); k++) {
    const l = Math.round((k * (L - 1)) / Math.max(Math.min(L, 12) - 1, 1));
    stops.push(`rgb(${layerColor(l, L).join(',')})`);
  }
  ramp.style.background = stops.length > 1 ? `linear-gradient(to right, ${stops.join(', ')})` : stops[0] || 'none';
  if (v) {
    v.setVisible('surfaces', $('show-surfaces').checked);
    v.setVisible('missed', $('show-missed').checked);
    v.setVisible('support', $('show-support').checked);
    v.setVisible('glyphs', $('axis-glyphs-toggle').checked);
  }
  applySurfaceLayer();
}

/** Show the layer surfaces up to the surface slider's layer (that one highlighted). */
function applySurfaceLayer() {
  const v = app.voxelView;
  const slider = $('layer-surface-slider');
  if (!v) {
    $('surface-layer-text').textContent = '—';
    delete slider.dataset.drawnTriangles;
    return;
  }
  const r = v.setSurfaceLayer(Number(slider.value));
  slider.value = String(r.hi);
  const stats = v.stats();
  slider.dataset.drawnTriangles = String(stats.drawnTriangles);
  $('surface-layer-text').textContent = v.surfaceLayerCount
    ? `${r.hi + 1} of ${v.surfaceLayerCount} (${stats.currentTriangles.toLocaleString('en')} triangles)` : 'no surfaces';
  app.viewer && app.viewer.requestRender();
}

function setVoxelLayerVisible(kind, visible) {
  if (!app.voxelView) return;
  app.voxelView.setVisible(kind, visible);
  if (kind === 'surfaces') applySurfaceLayer();
  app.viewer && app.viewer.requestRender();
}

function buildLegend() {
  const ul = $('legend');
  ul.replaceChildren();
  for (const f of FEATURES) {
    const li = document.createElement('li');
    const sw = document.createElement('span');
    sw.className = 'swatch';
    sw.style.background = featureCss(f.code);
    li.append(sw, f.name);
    ul.append(li);
  }
  // Iso-planar NL curves: adjacent curves alternate between two colours (shown with curves only).
  CURVE_COLORS.forEach((color, k) => {
    const li = document.createElement('li');
    li.dataset.testid = 'legend-curves';
    li.hidden = true;
    const sw = document.createElement('span');
    sw.className = 'swatch';
    sw.style.background = `rgb(${color.join(',')})`;
    li.append(sw, k === 0 ? 'NL curves 1, 3, …' : 'NL curves 2, 4, …');
    ul.append(li);
  });
}

// ---- operations -------------------------------------------------------------------------------

function updateButtons() {
  $('slice-button').disabled = !app.slicer || !app.mesh || !!app.busy;
  $('cancel-button').disabled = app.busy !== 'slicing';
  $('download-program').disabled = !app.result || !!app.busy;
  $('machine-toggle').disabled = !(app.result || app.replay) || !!app.busy;
  $('iso-compare-button').disabled = !app.slicer || !app.mesh || !!app.busy || !firstIso();
  $('iso-show-run').disabled = !app.compare || !!app.busy;
  $('demo-model').disabled = !app.slicer || !!app.busy;
  for (const b of document.querySelectorAll('[data-testid^="geo-use-"]')) b.disabled = !app.slicer || !app.mesh || !!app.busy;
}

/** Load mesh bytes; on failure the previous model stays loaded. Returns true on success. */
async function loadBytes(name, bytes, { frame = true } = {}) {
  if (!app.slicer) return false;
  if (app.busy === 'slicing') cancelSlice();
  while (app.busy) await nextFrame();
  app.busy = 'loading';
  clearError();
  setState('loading');
  setProgressText(`reading ${name}`, 0);
  updateButtons();
  try {
    // The facade keeps its own copy of the bytes (it re-sends them to a respawned worker).
    const { meshId, info, mesh } = await app.slicer.loadMesh(name, bytes, app.model.toPlacement());
    const previous = app.mesh;
    app.mesh = { name, meshId, info };
    if (previous && typeof app.slicer.unloadMesh === 'function') app.slicer.unloadMesh(previous.meshId).catch(() => {});
    app.placementDirty = false;
    showInfo(name, info);
    clearReport();
    await setPreview(null);
    if (app.viewer) {
      app.viewer.setModel(mesh);
      if (frame) app.viewer.frame();
    }
    setProgressText(`loaded ${name}: press Slice`, 0);
    setState('ready');
    return true;
  } catch (err) {
    showError(err);
    setProgressText(`could not load ${name}`, 0);
    setState('error');
    return false;
  } finally {
    app.busy = null;
    updateButtons();
  }
}

async function loadFile(file) {
  if (!file) return;
  let bytes;
  try {
    bytes = await file.arrayBuffer();
  } catch (err) {
    showError({ code: 'io_error', message: `cannot read ${file.name}: ${err.message}` });
    return;
  }
  await loadBytes(file.name, bytes);
}

/**
 * Replace the preview (null clears). Built in slices, so it does not hold the main thread.
 * fresh: a new result (not a switch between compared runs): the layer surfaces start hidden when
 * the paths are iso-planar NL curves (the surface would cover them), shown otherwise.
 */
async function setPreview(result, { fresh = false } = {}) {
  if (app.viewer) app.viewer.setPreview(null);
  if (app.geodesicView) app.geodesicView.dispose();
  if (app.multidirView) app.multidirView.dispose();
  app.preview = null;
  app.voxelView = null;
  app.geodesicView = null;
  app.multidirView = null;
  const buffers = result && result.preview;
  let preview = null;
  let voxel = null;
  let geodesic = null;
  let multidir = null;
  if (buffers && buffers.features && buffers.features.length) preview = await ToolpathPreview.build(buffers);
  if (hasVoxelBuffers(buffers)) {
    try {
      voxel = await VoxelView.build(buffers);
    } catch (err) {
      showError({ code: 'internal', message: `voxel view: ${err.message}` });
    }
  }
  if (hasGeodesicBuffers(buffers)) {
    try {
      geodesic = timed('geodesic-view', () => new GeodesicView(buffers, result.report && result.report.geodesic));
    } catch (err) {
      showError({ code: 'internal', message: `geodesic view: ${err.message}` });
    }
  }
  if (hasMultidirBuffers(buffers)) {
    try {
      multidir = timed('multidir-view', () => new MultidirView(buffers, result.report && result.report.multidir, result.mesh));
    } catch (err) {
      showError({ code: 'internal', message: `multidir view: ${err.message}` });
    }
  }
  if (fresh) $('show-surfaces').checked = !(preview && preview.curveCount > 0);
  if (preview || voxel || geodesic || multidir) {
    timed('set-preview', () => {
      if (preview) preview.setTravelVisible($('show-travel').checked);
      app.preview = preview;
      app.voxelView = voxel;
      app.geodesicView = geodesic;
      app.multidirView = multidir;
      // One object for the viewer: the tool-paths with the voxel, geodesic and multidir views inside.
      const root = preview ? preview.object : voxel ? voxel.object : geodesic ? geodesic.object : multidir.object;
      if (voxel && root !== voxel.object) root.add(voxel.object);
      if (geodesic && root !== geodesic.object) root.add(geodesic.object);
      if (multidir && root !== multidir.object) root.add(multidir.object);
      if (app.viewer) app.viewer.setPreview(root);
    });
  }
  timed('layer-sliders', () => {
    setupGeoBar();
    setupMultidirBar();
    // With iso-planar NL curves the range starts at their layer (the surface layer above its base).
    setupLayerSliders(app.preview ? app.preview.layerCount : 0, app.preview ? Math.max(app.preview.curveLayerMin, 0) : 0);
    setupVoxelBar();
  });
  $('iso-curve-count').textContent = String(app.preview ? app.preview.curveCount : 0);
  for (const li of document.querySelectorAll('[data-testid="legend-curves"]')) li.hidden = !(app.preview && app.preview.curveCount > 0);
}

async function slice() {
  if (!app.slicer || !app.mesh || app.busy) return;
  app.busy = 'slicing';
  app.abort = new AbortController();
  app.progress = newProgress(app.model.get('method'));
  $('stage-list').replaceChildren();
  clearError();
  setState('slicing');
  setProgressText('starting', 0);
  updateButtons();
  const started = performance.now();
  performance.mark('omnislice:slice-start');
  try {
    const settings = app.model.toSliceSettings();
    const result = await app.slicer.slice(app.mesh.meshId, settings, {
      onProgress,
      signal: app.abort.signal,
    });
    performance.mark('omnislice:result');
    await showResult(result, started);
    app.resultSettings = settings;
  } catch (err) {
    // A live search chart goes: the report group shows the last result again.
    if (app.progress.liveDraws.length > 0) showMultidirReport(app.result?.report?.multidir ?? null);
    if (err && err.code === 'cancelled') {
      showError(err);
      setProgressText('cancelled', 0);
      setState('cancelled');
    } else {
      showError(err);
      setProgressText('slicing failed', 0);
      setState('error');
    }
  } finally {
    app.busy = null;
    app.abort = null;
    updateButtons();
  }
}

/**
 * Show a slice result: report, model, preview (tool-paths and the voxel view), machine view; the
 * summary line and the page state 'done' last. Each step is its own task, so none of them holds
 * the main thread for long.
 */
async function showResult(result, started) {
  app.busy = 'showing';
  await nextFrame();
  timed('show-report', () => {
    clearCompare();
    app.result = result;
    app.resultSettings = null;
    app.replay = null;
    showReport(result.report);
    setDownloadLabel(result.programExtension);
    const bed = parseVector(result.report && result.report.settings && result.report.settings.bed_size);
    if (bed && app.viewer && bed.some((x, i) => x !== app.viewer.bedSize[i])) app.viewer.setBed(bed);
    if (result.info) showInfo(app.mesh.name, result.info);
  });
  if (result.mesh && app.viewer) timed('set-model', () => app.viewer.setModel(result.mesh));
  if (app.placementDirty && app.viewer) app.viewer.frame();
  app.placementDirty = false;
  await nextFrame();
  await setPreview(result, { fresh: true });
  performance.mark('omnislice:preview-built');
  if ($('machine-toggle').checked) timed('machine-view', () => openMachineView());
  app.sliceCount += 1;
  document.body.dataset.sliceCount = String(app.sliceCount);
  const wall = ((performance.now() - started) / 1000).toFixed(2);
  const voxel = result.report && result.report.voxel;
  const geo = result.report && result.report.geodesic;
  const md = result.report && result.report.multidir;
  const summary = geo ? geodesicDoneSummary(geo) : md ? multidirDoneSummary(md) : voxel ? voxelDoneSummary(voxel) : '';
  setProgressText(`done in ${wall} s${summary ? `: ${summary}` : ''}`, 1);
  showStages({ finished: true });
  setState('done');
}

function cancelSlice() {
  if (app.abort) {
    setProgressText('cancelling…');
    app.abort.abort();
  }
}

function download() {
  if (!app.result || !(app.result.programBytes instanceof Uint8Array)) return;
  const extension = programExtension(app.result.programExtension);
  // The Blob is made only now, from the bytes: the program is never decoded on the main thread.
  const url = URL.createObjectURL(new Blob([app.result.programBytes], { type: PROGRAM_KINDS[extension].mime }));
  const a = document.createElement('a');
  a.href = url;
  a.download = programFileName(app.mesh ? app.mesh.name : 'model', extension);
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 30000);
}

// ---- machine profile ------------------------------------------------------------------------

/** Load a user's machine profile: the core checks it; errors show with their code. */
async function loadMachineFile(file) {
  if (!file || !app.slicer) return;
  clearError();
  let text;
  try {
    text = await file.text();
  } catch (err) {
    showError({ code: 'io_error', message: `cannot read ${file.name}: ${err.message}` });
    return;
  }
  try {
    const { profile, json } = await app.slicer.parseMachine(text);
    const kind = profile.kind;
    if (!['cartesian3', 'rotary4', 'table5', 'robot6'].includes(kind)) {
      throw { code: 'invalid_option', message: `machine JSON: unknown kind "${kind}" (cartesian3, rotary4, table5, robot6)` };
    }
    app.machineFiles.set(json, file.name);
    app.history.execute(new SetSettingCommand(app.model, 'machine_json', json));
  } catch (err) {
    showError({ code: (err && err.code) || 'parse_error', message: `${file.name}: ${(err && err.message) || err}` });
  }
}

/** Replay a program file (G-code, robot CSV, URScript) through its declared machine, animated. */
async function replayProgramFile(file) {
  if (!file || !app.slicer || app.busy) return;
  clearError();
  try {
    const text = await file.text();
    const r = await app.slicer.replay(text);
    app.replay = { name: file.name, profile: r.profile, preview: r.preview };
    $('machine-toggle').checked = true;
    updateButtons();
    openMachineView();
  } catch (err) {
    showError({ code: (err && err.code) || 'io_error', message: `${file.name}: ${(err && err.message) || err}` });
  }
}

/** Download the selected built-in profile as JSON (a template for a user's own profile file). */
async function saveBuiltinProfile() {
  if (!app.slicer) return;
  try {
    const name = app.model.get('machine');
    const list = await app.slicer.machines({ nozzle: app.model.get('nozzle') });
    const found = list.find((x) => x.name === name);
    if (!found) throw { code: 'invalid_option', message: `no built-in machine ${name}` };
    const url = URL.createObjectURL(new Blob([`${JSON.stringify(found.profile, null, 2)}\n`], { type: 'application/json' }));
    const a = document.createElement('a');
    a.href = url;
    a.download = `${name}.json`;
    document.body.append(a);
    a.click();
    a.remove();
    setTimeout(() => URL.revokeObjectURL(url), 30000);
  } catch (err) {
    showError(err);
  }
}

/** The machine panel follows the settings: which profile is used, the built-in select's state. */
function showMachineProfile() {
  const json = app.model.get('machine_json');
  const fromFile = !!json;
  $('machine').disabled = fromFile;
  $('machine-builtin').hidden = !fromFile;
  const kind = selectedMachineKind(app.model.values);
  $('machine-profile').textContent = fromFile
    ? `profile ${app.machineFiles.get(json) || 'from a file'} (${kind})`
    : `built-in profile ${app.model.get('machine')}`;
  $('machine-profile').dataset.kind = kind;
  // The voxel and surface methods tilt the nozzle: they need two rotary axes (table5) or a robot.
  const hint = $('method-hint');
  const method = app.model.get('method');
  const needsTilt = ['voxel', 'surface', 'geodesic'].includes(method) && !['table5', 'robot6'].includes(kind);
  // The multidir method turns the part between parts: one rotary axis (rotary4) is enough.
  const needsTurn = method === 'multidir' && kind === 'cartesian3';
  hint.hidden = !needsTilt && !needsTurn;
  hint.textContent = needsTilt
    ? `the ${method} method ${method === 'surface' ? 'keeps the nozzle along the surface normal' : 'tilts the nozzle'}: choose table5 or a robot (${kind} has no tilt axes)`
    : needsTurn ? 'the multidir method turns the part between parts: choose rotary4, table5 or a robot (cartesian3 has no rotary axis)' : '';
}

// ---- machine animation ----------------------------------------------------------------------

/**
 * Build the machine view of the replayed program, else of the current result, and show it in
 * place of the part view.
 */
function openMachineView() {
  closeMachineView();
  const r = app.replay || app.result;
  if (!r || !app.viewer) return;
  const profile = app.replay ? app.replay.profile : r.report && r.report.machine_profile;
  try {
    if (!profile || !r.preview || !r.preview.machine || r.preview.machine.length === 0) {
      throw { code: 'internal', message: 'this result has no machine motion to animate (report.machine_profile, preview.machine)' };
    }
    app.machineView = new MachineView(profile, r.preview, app.replay ? null : r.mesh);
  } catch (err) {
    showError({ code: err.code || 'internal', message: `machine view: ${err.message}` });
    $('machine-toggle').checked = false;
    return;
  }
  const slider = $('machine-step');
  slider.max = String(Math.max(app.machineView.stepCount - 1, 0));
  slider.value = String(app.machineView.stepCount - 1);
  $('machine-bar').hidden = false;
  app.viewer.setMachine(app.machineView.object);
  showMachineStep(app.machineView.stepCount - 1);
}

function closeMachineView() {
  stopMachinePlay();
  if (app.machineView) {
    if (app.viewer) app.viewer.setMachine(null);
    app.machineView.dispose();
    app.machineView = null;
  }
  $('machine-bar').hidden = true;
  delete $('machine-step').dataset.tipError;
}

/** Pose the machine at move s; the texts and data-tip-error (mm) follow. */
function showMachineStep(s) {
  const view = app.machineView;
  if (!view) return;
  const { step, values, tipError } = view.setStep(s);
  const slider = $('machine-step');
  slider.value = String(step);
  slider.dataset.tipError = String(tipError);
  slider.dataset.step = String(step);
  $('machine-step-text').textContent = `${app.replay ? `${app.replay.name}: ` : ''}move ${step + 1} of ${view.stepCount}`;
  const names = machineAxisNames(view.kind);
  $('machine-values').textContent = values.map((v, i) => {
    const angle = view.kind === 'robot6' ? `${((v * 180) / Math.PI).toFixed(1)}°` : i >= 3 ? `${v.toFixed(2)}°` : v.toFixed(2);
    return `${names[i]} ${angle}`;
  }).join('  ');
  $('machine-tip-error').textContent = `tip error ${tipError.toExponential(1)} mm`;
  app.viewer.requestRender();
}

function stopMachinePlay() {
  if (app.machinePlay) cancelAnimationFrame(app.machinePlay);
  app.machinePlay = 0;
  $('machine-play').textContent = '▶';
  $('machine-play').setAttribute('aria-pressed', 'false');
}

/** Play from the current move (from the start when at the end); about 20 s for a whole program. */
function toggleMachinePlay() {
  const view = app.machineView;
  if (!view) return;
  if (app.machinePlay) {
    stopMachinePlay();
    return;
  }
  let step = view.step >= view.stepCount - 1 ? 0 : view.step;
  const perFrame = Math.max(1, Math.round(view.stepCount / (20 * 60)));
  $('machine-play').textContent = '❚❚';
  $('machine-play').setAttribute('aria-pressed', 'true');
  const tick = () => {
    step = Math.min(step + perFrame, view.stepCount - 1);
    showMachineStep(step);
    if (step >= view.stepCount - 1 || app.machineView !== view) {
      stopMachinePlay();
      return;
    }
    app.machinePlay = requestAnimationFrame(tick);
  };
  app.machinePlay = requestAnimationFrame(tick);
}

// ---- placement edits ----------------------------------------------------------------------

let placeTimer = 0;
function onSettingChange(event) {
  if (!isPlacementKey(event.detail.key) || !app.mesh) return;
  app.placementDirty = true;
  // Place again after a short pause so the model shows the new placement; if the engine is busy,
  // the next slice applies it (slice() sends the placement keys too).
  clearTimeout(placeTimer);
  placeTimer = setTimeout(() => {
    if (!app.busy && app.mesh && app.placementDirty) applyPlacement();
  }, 250);
}

/** Show the loaded mesh with the current placement (the old tool-paths no longer match it). */
async function applyPlacement() {
  app.busy = 'placing';
  clearError();
  setState('loading');
  setProgressText(`placing ${app.mesh.name}`, 0);
  updateButtons();
  try {
    const { info, mesh } = await app.slicer.info(app.mesh.meshId, app.model.toPlacement());
    app.placementDirty = false;
    showInfo(app.mesh.name, info);
    clearReport();
    await setPreview(null);
    if (app.viewer) {
      app.viewer.setModel(mesh);
      app.viewer.frame();
    }
    setProgressText(`placed ${app.mesh.name}: press Slice`, 0);
    setState('ready');
  } catch (err) {
    showError(err);
    setProgressText('placement failed', 0);
    setState('error');
  } finally {
    app.busy = null;
    updateButtons();
  }
}

// ---- start-up -----------------------------------------------------------------------------------

function wireUi() {
  createSettingsPanel(document.getElementById('settings-panel'), app.model, app.history,
    { groupHosts: { Machine: document.getElementById('machine-fields') } });
  app.model.addEventListener('change', onSettingChange);
  app.model.addEventListener('change', showMachineProfile);
  showMachineProfile();
  $('machine-file').addEventListener('change', (e) => {
    const file = e.target.files && e.target.files[0];
    loadMachineFile(file).finally(() => { e.target.value = ''; });
  });
  $('machine-save').addEventListener('click', () => saveBuiltinProfile());
  $('program-file').addEventListener('change', (e) => {
    const file = e.target.files && e.target.files[0];
    replayProgramFile(file).finally(() => { e.target.value = ''; });
  });
  $('machine-builtin').addEventListener('click', () => {
    app.history.execute(new SetSettingCommand(app.model, 'machine_json', ''));
  });
  $('machine-toggle').addEventListener('change', (e) => {
    if (e.target.checked) openMachineView();
    else closeMachineView();
  });
  $('machine-step').addEventListener('input', (e) => {
    stopMachinePlay();
    showMachineStep(Number(e.target.value));
  });
  $('machine-play').addEventListener('click', () => toggleMachinePlay());
  buildLegend();
  $('file-input').addEventListener('change', (e) => {
    const file = e.target.files && e.target.files[0];
    loadFile(file).finally(() => { e.target.value = ''; });
  });
  $('slice-button').addEventListener('click', () => slice());
  $('iso-polar').addEventListener('click', (e) => onPolarClick(e));
  $('iso-compare-theta').addEventListener('input', () => renderPolar(firstIso()));
  $('iso-compare-button').addEventListener('click', () => runCompare());
  $('iso-show-run').addEventListener('change', (e) => {
    if (app.busy) return;
    app.busy = 'showing';
    updateButtons();
    showRun(Number(e.target.value)).finally(() => {
      app.busy = null;
      updateButtons();
    });
  });
  $('demo-model').addEventListener('change', (e) => {
    const demo = DEMOS[e.target.value];
    e.target.value = '';
    if (demo) loadDemo(demo, { sliceAfter: true });
  });
  $('cancel-button').addEventListener('click', () => cancelSlice());
  $('download-program').addEventListener('click', () => download());
  $('layer-min-slider').addEventListener('input', (e) => applyLayerRange(e.target));
  $('layer-slider').addEventListener('input', (e) => {
    applyLayerRange(e.target);
    // The surfaces follow the tool-paths' top layer.
    if (app.voxelView) {
      $('layer-surface-slider').value = e.target.value;
      applySurfaceLayer();
    }
  });
  $('layer-surface-slider').addEventListener('input', (e) => {
    applySurfaceLayer();
    // The tool-paths (and glyphs) follow the surfaces' layer.
    const hi = $('layer-slider');
    if (!hi.disabled) {
      hi.value = e.target.value;
      applyLayerRange(hi);
    }
  });
  $('show-surfaces').addEventListener('change', (e) => setVoxelLayerVisible('surfaces', e.target.checked));
  $('show-missed').addEventListener('change', (e) => setVoxelLayerVisible('missed', e.target.checked));
  $('show-support').addEventListener('change', (e) => setVoxelLayerVisible('support', e.target.checked));
  $('axis-glyphs-toggle').addEventListener('change', (e) => setVoxelLayerVisible('glyphs', e.target.checked));
  $('show-field').addEventListener('change', (e) => setGeoLayerVisible('field', e.target.checked));
  $('show-tree').addEventListener('change', (e) => setGeoLayerVisible('tree', e.target.checked));
  $('show-air').addEventListener('change', (e) => setGeoLayerVisible('air', e.target.checked));
  $('geo-step-slider').addEventListener('input', () => applyGeoStep());
  $('show-parts').addEventListener('change', (e) => setMultidirOption((v) => v.setVisible('parts', e.target.checked)));
  $('show-arrows').addEventListener('change', (e) => setMultidirOption((v) => v.setVisible('arrows', e.target.checked)));
  $('md-risky').addEventListener('change', (e) => setMultidirOption((v) => v.setRisky(e.target.value)));
  $('md-order-slider').addEventListener('input', () => applyMultidirOrder());
  $('show-travel').addEventListener('change', (e) => {
    if (app.preview) app.preview.setTravelVisible(e.target.checked);
    app.viewer && app.viewer.requestRender();
  });
  $('show-model').addEventListener('change', (e) => app.viewer && app.viewer.setModelVisible(e.target.checked));
  const view = $('viewer');
  view.addEventListener('dragover', (e) => {
    e.preventDefault();
    e.dataTransfer.dropEffect = 'copy';
    view.classList.add('dragging');
  });
  view.addEventListener('dragleave', () => view.classList.remove('dragging'));
  view.addEventListener('drop', (e) => {
    e.preventDefault();
    view.classList.remove('dragging');
    const file = e.dataTransfer.files && e.dataTransfer.files[0];
    loadFile(file);
  });
  window.addEventListener('keydown', (e) => {
    const typing = e.target instanceof HTMLInputElement && e.target.type !== 'checkbox' && e.target.type !== 'range';
    if (typing || !(e.ctrlKey || e.metaKey) || e.key.toLowerCase() !== 'z') return;
    e.preventDefault();
    if (e.shiftKey) app.history.redo();
    else app.history.undo();
  });
}

function createViewer() {
  try {
    app.viewer = new Viewer(document.getElementById('canvas-host'));
    app.viewer.frame();
  } catch (err) {
    const msg = $('view-message');
    msg.textContent = `3D view unavailable (${err.message}); slicing and downloads still work.`;
    msg.hidden = false;
  }
}

/** Fetch and load a bundled demo model; its settings (e.g. the surface method) go through the history. */
async function loadDemo(demo, { sliceAfter = false } = {}) {
  try {
    const response = await fetch(demo.url);
    if (!response.ok) throw Object.assign(new Error(`${demo.url}: HTTP ${response.status}`), { code: 'io_error' });
    const bytes = await response.arrayBuffer();
    for (const [key, value] of Object.entries(demo.settings || {})) {
      if (app.model.get(key) !== value) app.history.execute(new SetSettingCommand(app.model, key, value));
    }
    if (demo.tilt && !['table5', 'robot6'].includes(selectedMachineKind(app.model.values))) {
      if (app.model.get('machine_json')) app.history.execute(new SetSettingCommand(app.model, 'machine_json', ''));
      app.history.execute(new SetSettingCommand(app.model, 'machine', demo.tilt));
    }
    if (await loadBytes(demo.name, bytes) && sliceAfter) await slice();
  } catch (err) {
    showError(err);
    setState('error');
  }
}

async function start() {
  wireUi();
  createViewer();
  setState('starting');
  updateButtons();
  try {
    // Imported here, not statically, so the panel still works and reports the problem if the
    // engine cannot load.
    const { createSlicer } = await import('/workers/engine.js');
    app.slicer = await createSlicer();
  } catch (err) {
    showError({ code: err.code || 'engine_unavailable', message: `the slicing engine did not start: ${err.message}` });
    setProgressText('engine unavailable', 0);
    setState('error');
    return;
  }
  updateButtons();
  await loadDemo(DEMOS.overhang, { sliceAfter: true });
}

/** Read-only view of the app for diagnostics and tests. */
window.omnislice = {
  get state() { return document.body.dataset.state; },
  get report() { return app.result ? app.result.report : null; },
  get info() { return app.mesh ? app.mesh.info : null; },
  get previewSegments() { return app.preview ? app.preview.segmentCount : 0; },
  get featureCounts() { return app.preview ? app.preview.featureCounts : null; },
  get drawnSegments() { return app.preview ? app.preview.drawnSegments() : [0, 0]; },
  get settings() { return app.model.toSettings(); },
  get history() { return app.history.serialize(); },
  get programExtension() { return app.result ? app.result.programExtension : null; },
  /**
   * The iso-planar view: {curveCount (NL curves drawn in alternating colours), shownRun,
   * compare: {theta, report} | null, rows (the comparison table)}, or null without report.isoplanar.
   */
  get isoplanar() {
    const iso = firstIso();
    if (!iso) return null;
    return {
      curveCount: app.preview ? app.preview.curveCount : 0,
      shownRun: app.shownRun,
      compare: app.compare ? { theta: app.compare.theta, report: app.compare.result.report } : null,
      rows: comparisonRows(compareRuns()),
    };
  },
  /** The voxel view: what it holds and draws (VoxelView.stats()), or null. */
  get voxel() { return app.voxelView ? app.voxelView.stats() : null; },
  /** The geodesic view: what it holds and draws (GeodesicView.stats()), or null. */
  get geodesic() { return app.geodesicView ? app.geodesicView.stats() : null; },
  /** The multidir view: what it holds and draws (MultidirView.stats()), or null. */
  get multidir() { return app.multidirView ? app.multidirView.stats() : null; },
  /**
   * The search levels of the last slice's multidir decomposition: {levels: progress.search of
   * every event in arrival order, liveDraws: the live J_G chart's values at each of its drawings}.
   */
  get searchProgress() {
    return { levels: app.progress.levels.map((s) => ({ ...s })), liveDraws: app.progress.liveDraws.map((v) => v.slice()) };
  },
  /** The stage details of the last slice (a search level's text for 'decompose'): {stage: text}. */
  get stageDetails() {
    return Object.fromEntries([...app.progress.stages].filter(([, e]) => e.detail).map(([k, e]) => [k, e.detail]));
  },
  /** The progress stages of the last slice in arrival order: [[stage, fraction, ms]]. */
  get stages() {
    const list = [...app.progress.stages];
    return list.map(([k, e], i) => [k, e.fraction, (i + 1 < list.length ? list[i + 1][1].start : e.end) - e.start]);
  },
  /**
   * Test hook: show a result object shaped like slicer.slice()'s (programBytes, programExtension,
   * report, preview, mesh) as if the engine had produced it; resolves when it is drawn.
   */
  async _showResultForTest(result) {
    if (app.busy) throw new Error('busy');
    try {
      await showResult(result, performance.now());
    } finally {
      app.busy = null;
      updateButtons();
    }
  },
  /** The machine animation: {kind, step, steps, tipError (mm, measured in the scene)} or null. */
  get machine() {
    const v = app.machineView;
    return v ? { kind: v.kind, step: v.step, steps: v.stepCount, tipError: v.tipError, replay: app.replay ? app.replay.name : null } : null;
  },
};

start();
