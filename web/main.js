// SPDX-License-Identifier: MIT
// App wiring: file input and drag-and-drop -> slicer.loadMesh; Slice/Cancel -> slicer.slice with
// progress; result -> viewer (model + tool-path preview), report figures and G-code download.
// All heavy work runs in the engine's worker; the main thread only moves typed arrays around.
// The page's state is mirrored on <body data-state> (starting, loading, ready, slicing, done,
// error, cancelled) and <body data-slice-count>, which the end-to-end tests wait on.
import { Viewer } from './viewer.js';
import { ToolpathPreview, FEATURES, featureCss } from './preview.js';
import { SettingsModel, History, createSettingsPanel, PLACEMENT_KEYS } from './settings-panel.js';

const DEMO_URL = '/models/demo-overhang.stl';
const DEMO_NAME = 'demo-overhang.stl';
// Share of the progress bar per stage (stages arrive in this order).
const STAGE_WEIGHTS = { read: 0.04, validate: 0.06, place: 0.02, slice: 0.28, toolpath: 0.45, program: 0.15 };
const STAGE_ORDER = Object.keys(STAGE_WEIGHTS);
const FILAMENT_AREA_MM2 = Math.PI * (1.75 / 2) ** 2;
const PLA_G_PER_MM3 = 1.24e-3;

const $ = (id) => document.querySelector(`[data-testid="${id}"]`);

const app = {
  slicer: null,
  viewer: null,
  preview: null,
  model: new SettingsModel(),
  history: new History(),
  mesh: null,        // {name, meshId, info} of the loaded mesh
  result: null,      // last successful slice result
  busy: null,        // 'loading' | 'placing' | 'slicing' | 'showing' | null
  abort: null,       // AbortController of the running slice
  placementDirty: false,
  sliceCount: 0,
  progress: { stage: '', fraction: 0, overall: 0, pending: false },
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

/** Progress callback: keep the latest value, paint once per frame. */
function onProgress({ stage, fraction }) {
  const p = app.progress;
  p.stage = stage;
  p.fraction = Math.min(Math.max(Number(fraction) || 0, 0), 1);
  const k = STAGE_ORDER.indexOf(stage);
  if (k >= 0) {
    let before = 0;
    for (let i = 0; i < k; i++) before += STAGE_WEIGHTS[STAGE_ORDER[i]];
    p.overall = Math.max(p.overall, before + STAGE_WEIGHTS[stage] * p.fraction);
  }
  if (p.pending) return;
  p.pending = true;
  requestAnimationFrame(() => {
    p.pending = false;
    if (app.busy) setProgressText(`${p.stage} ${Math.round(p.fraction * 100)}%`, p.overall);
  });
}

// ---- figures --------------------------------------------------------------------------------------

function formatTime(seconds) {
  if (!Number.isFinite(seconds)) return '—';
  const s = Math.round(seconds);
  const h = Math.floor(s / 3600);
  const m = Math.floor((s % 3600) / 60);
  return h > 0 ? `${h} h ${String(m).padStart(2, '0')} min` : m > 0 ? `${m} min ${String(s % 60).padStart(2, '0')} s` : `${s} s`;
}

function formatLength(mm) {
  if (!Number.isFinite(mm)) return '—';
  return mm >= 1000 ? `${(mm / 1000).toFixed(2)} m` : `${mm.toFixed(1)} mm`;
}

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

function describeList(value) {
  if (value == null) return [];
  if (Array.isArray(value)) return value.map((v) => (typeof v === 'string' ? v : v.message || JSON.stringify(v)));
  if (typeof value === 'object') {
    return Object.entries(value)
      .filter(([, v]) => v && v !== 0)
      .map(([k, v]) => (v === true ? k : `${k}: ${typeof v === 'object' ? JSON.stringify(v) : v}`));
  }
  return [String(value)];
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
  $('report-time').textContent = formatTime(r.estimated_time_s);
  if (Number.isFinite(r.extrusion_mm)) {
    const grams = r.extrusion_mm * FILAMENT_AREA_MM2 * PLA_G_PER_MM3;
    $('report-filament').textContent = `${formatLength(r.extrusion_mm)} (${grams.toFixed(1)} g PLA)`;
  } else {
    $('report-filament').textContent = '—';
  }
  $('report-path').textContent = formatLength(r.path_mm);
  const t = r.timings_ms && typeof r.timings_ms === 'object' ? r.timings_ms : null;
  const total = t && (Number.isFinite(t.total) ? t.total
    : Object.values(t).filter(Number.isFinite).reduce((a, b) => a + b, 0));
  $('report-took').textContent = t ? `${(total / 1000).toFixed(2)} s in the engine` : '—';
}

function clearReport() {
  showReport(null);
  app.result = null;
  $('download-program').disabled = true;
}

// ---- layer range ------------------------------------------------------------------------------

function setupLayerSliders(layerCount) {
  const lo = $('layer-min-slider');
  const hi = $('layer-slider');
  const last = Math.max(layerCount - 1, 0);
  for (const s of [lo, hi]) {
    s.max = String(last);
    s.disabled = layerCount === 0;
  }
  lo.value = '0';
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
}

// ---- operations -------------------------------------------------------------------------------

function updateButtons() {
  $('slice-button').disabled = !app.slicer || !app.mesh || !!app.busy;
  $('cancel-button').disabled = app.busy !== 'slicing';
  $('download-program').disabled = !app.result || !!app.busy;
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

/** Replace the preview (null clears). Built in slices, so it does not hold the main thread. */
async function setPreview(result) {
  if (app.viewer) app.viewer.setPreview(null);
  app.preview = null;
  if (result && result.preview && result.preview.features && result.preview.features.length) {
    const preview = await ToolpathPreview.build(result.preview);
    timed('set-preview', () => {
      preview.setTravelVisible($('show-travel').checked);
      app.preview = preview;
      if (app.viewer) app.viewer.setPreview(preview.object);
    });
  }
  timed('layer-sliders', () => setupLayerSliders(app.preview ? app.preview.layerCount : 0));
}

async function slice() {
  if (!app.slicer || !app.mesh || app.busy) return;
  app.busy = 'slicing';
  app.abort = new AbortController();
  app.progress = { stage: '', fraction: 0, overall: 0, pending: false };
  clearError();
  setState('slicing');
  setProgressText('starting', 0);
  updateButtons();
  const started = performance.now();
  performance.mark('omnislice:slice-start');
  try {
    const result = await app.slicer.slice(app.mesh.meshId, app.model.toSettings(), {
      onProgress,
      signal: app.abort.signal,
    });
    performance.mark('omnislice:result');
    app.busy = 'showing';
    // Each step below is its own task, so none of them holds the main thread for long.
    await nextFrame();
    timed('show-report', () => {
      app.result = result;
      showReport(result.report);
      const bed = parseVector(result.report && result.report.settings && result.report.settings.bed_size);
      if (bed && app.viewer && bed.some((x, i) => x !== app.viewer.bedSize[i])) app.viewer.setBed(bed);
      if (result.info) showInfo(app.mesh.name, result.info);
    });
    if (result.mesh && app.viewer) timed('set-model', () => app.viewer.setModel(result.mesh));
    if (app.placementDirty && app.viewer) app.viewer.frame();
    app.placementDirty = false;
    await nextFrame();
    await setPreview(result);
    performance.mark('omnislice:preview-built');
    app.sliceCount += 1;
    document.body.dataset.sliceCount = String(app.sliceCount);
    const wall = ((performance.now() - started) / 1000).toFixed(2);
    setProgressText(`done in ${wall} s`, 1);
    setState('done');
  } catch (err) {
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

function cancelSlice() {
  if (app.abort) {
    setProgressText('cancelling…');
    app.abort.abort();
  }
}

function download() {
  if (!app.result || !(app.result.programBytes instanceof Uint8Array)) return;
  const base = (app.mesh ? app.mesh.name : 'model').replace(/\.[^.]*$/, '') || 'model';
  // The Blob is made only now, from the bytes: the G-code is never decoded on the main thread.
  const url = URL.createObjectURL(new Blob([app.result.programBytes], { type: 'text/x-gcode' }));
  const a = document.createElement('a');
  a.href = url;
  a.download = `${base}.gcode`;
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 30000);
}

// ---- placement edits ----------------------------------------------------------------------

let placeTimer = 0;
function onSettingChange(event) {
  if (!PLACEMENT_KEYS.includes(event.detail.key) || !app.mesh) return;
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
  createSettingsPanel(document.getElementById('settings-panel'), app.model, app.history);
  app.model.addEventListener('change', onSettingChange);
  buildLegend();
  $('file-input').addEventListener('change', (e) => {
    const file = e.target.files && e.target.files[0];
    loadFile(file).finally(() => { e.target.value = ''; });
  });
  $('slice-button').addEventListener('click', () => slice());
  $('cancel-button').addEventListener('click', () => cancelSlice());
  $('download-program').addEventListener('click', () => download());
  $('layer-min-slider').addEventListener('input', (e) => applyLayerRange(e.target));
  $('layer-slider').addEventListener('input', (e) => applyLayerRange(e.target));
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
  try {
    const response = await fetch(DEMO_URL);
    if (!response.ok) throw Object.assign(new Error(`${DEMO_URL}: HTTP ${response.status}`), { code: 'io_error' });
    const bytes = await response.arrayBuffer();
    if (await loadBytes(DEMO_NAME, bytes)) await slice();
  } catch (err) {
    showError(err);
    setState('error');
  }
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
};

start();
