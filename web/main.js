// SPDX-License-Identifier: MIT
// The page's start-up and wiring: the app state, the engine (started in its worker), the viewer,
// the settings and machine panels (built once the engine gives its settings table: defaults,
// ranges and choices are the core's), and the operations the controls start: load a mesh (file
// input, drag-and-drop, demo menu), place it again after a placement edit, slice with progress and
// cancel, show the result (report, model, views, machine animation), download the program. A slice
// the core refuses as unsound (error code unsound_program) still shows what it measured: its
// report, model and views, with the error and without a program (app.refused).
// What a method shows comes from the method registry (methods/index.js): each method's module
// draws its report section and builds its view when the result carries them.
// All heavy work runs in the engine's worker; the main thread only moves typed arrays around.
// The page's state is mirrored on <body data-state> (starting, loading, ready, slicing, done,
// error, cancelled) and <body data-slice-count>, which the end-to-end tests wait on.
import { timed } from './block-runner.js';
import { DEMOS, demoOfQuery } from './demo-models.js';
import { closeMachineView, openMachineView, showMotion, wireMachinePanel } from './machine-panel.js';
import {
  buildViews, disposeViews, doneSummary, enablePanels, methodNamed, progressDetail, resetPanels, setLayerRange,
  setupViews, showProgress, showReports, sliceFailed, viewRoot, wirePanels,
} from './methods/index.js';
import { TILT_KINDS } from './methods/machine-needs.js';
import { showInfo } from './model-panel.js';
import { installPageApi } from './page-api.js';
import { byTestId as $, downloadBlob, onFileChosen } from './panel-dom.js';
import { isPlacementKey } from './placement.js';
import { PROGRAM_KINDS, programExtension, programFileName } from './program-file.js';
import { selectedMachineKind, settingsFields } from './settings-fields.js';
import { History, SetSettingCommand, SettingsModel, createSettingsPanel } from './settings-panel.js';
import {
  clearError, newProgress, progressText, recordProgress, setPageState, setProgressText, showError, showStages,
} from './status-panel.js';
import { Viewer } from './viewer.js';

/** The app state: the only state the page keeps (the method modules keep theirs in it too). */
const app = {
  slicer: null,
  viewer: null,
  views: {},         // the shown result's views by method name (planar: the ToolpathPreview; voxel, geodesic, multidir)
  model: null,       // the SettingsModel, made at start-up over the engine's settings table
  history: new History(),
  mesh: null,        // {name, meshId, info} of the loaded mesh
  result: null,      // last successful slice result
  refused: null,     // the refused slice shown instead ({report, info, preview, mesh} of its unsound_program error)
  busy: null,        // 'loading' | 'placing' | 'slicing' | 'showing' | null
  abort: null,       // AbortController of the running slice
  placementDirty: false,
  placeTimer: 0,     // timeout of the placement after an edit
  sliceCount: 0,
  progress: newProgress(methodNamed('planar').data.stageWeights),
  machineFiles: new Map(), // machine_json text -> file name it was loaded from (undo may bring any back)
  machineView: null, // MachineView of app.replay or app.result while the machine toggle is on
  replay: null,      // {name, profile, preview} of a replayed program file (shown instead of the result)
  machinePlay: 0,    // requestAnimationFrame id while playing
  resultSettings: null, // the slice settings app.result was made with (the compare run reuses them)
  compare: null,     // {theta, result} of the iso-planar comparison run (app.result stays the first)
  shownRun: 0,       // 0: app.result's paths are drawn, 1: app.compare's
  compareCount: 0,
  // The operations a method's panel may start.
  actions: { slice, runSlice, setPreview, applyLayerRange, updateButtons, showResult },
};

function nextFrame() {
  return new Promise((resolve) => requestAnimationFrame(() => setTimeout(resolve, 0)));
}

/** Progress callback: keep every event, paint once per frame. */
function onProgress(event) {
  const p = app.progress;
  recordProgress(p, event, { describeSearch: progressDetail });
  if (p.pending) return;
  p.pending = true;
  requestAnimationFrame(() => {
    p.pending = false;
    if (app.busy && app.progress === p) {
      setProgressText(progressText(p), p.overall);
      showStages(p);
      showProgress(app, p);
    }
  });
}

// ---- model and report ---------------------------------------------------------------------------

/** 'x,y,z' (or [x, y, z]) -> three finite numbers, else null. */
function parseVector(value) {
  const parts = Array.isArray(value) ? value.map(Number) : typeof value === 'string' ? value.split(',').map(Number) : [];
  return parts.length === 3 && parts.every(Number.isFinite) ? parts : null;
}

/** The report of every method that has a section in it, and the motion figures. */
function showReport(report) {
  showReports(app, report);
  showMotion(report);
}

function clearReport() {
  resetPanels(app);
  showReport(null);
  app.result = null;
  app.refused = null;
  app.replay = null;
  $('download-program').disabled = true;
  setDownloadLabel('gcode');
  closeMachineView(app);
}

function setDownloadLabel(extension) {
  $('download-program').textContent = `Download ${PROGRAM_KINDS[programExtension(extension)].label}`;
}

// ---- layer range and views ----------------------------------------------------------------------

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

/** Show the layers between the two sliders (the one moved, `changed`, pushes the other). */
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
  const n = app.views.planar ? app.views.planar.layerCount : 0;
  $('layer-text').textContent = n ? `${a + 1}–${b + 1} of ${n}` : '—';
  setLayerRange(app, a, b, b >= Number(hi.max));
}

/**
 * Replace the views (null clears). Built in slices, so it does not hold the main thread.
 * fresh: a new result (not a switch between compared runs).
 */
async function setPreview(result, { fresh = false } = {}) {
  if (app.viewer) app.viewer.setPreview(null);
  disposeViews(app.views);
  app.views = {};
  const views = await buildViews(result, { onError: showError });
  if (Object.keys(views).length) {
    timed('set-preview', () => {
      app.views = views;
      if (app.viewer) app.viewer.setPreview(viewRoot(views));
    });
  }
  timed('layer-sliders', () => {
    setupViews(app, { fresh });
    // With iso-planar NL curves the range starts at their layer (the surface layer above its base).
    const preview = app.views.planar;
    setupLayerSliders(preview ? preview.layerCount : 0, preview ? Math.max(preview.curveLayerMin, 0) : 0);
  });
}

// ---- operations -------------------------------------------------------------------------------

function updateButtons() {
  $('slice-button').disabled = !app.slicer || !app.mesh || !!app.busy;
  $('cancel-button').disabled = app.busy !== 'slicing';
  $('download-program').disabled = !app.result || !!app.busy;
  $('machine-toggle').disabled = !(app.result || app.replay) || !!app.busy;
  $('demo-model').disabled = !app.slicer || !!app.busy;
  enablePanels(app);
}

/**
 * Run an engine task that is not a slice (loading, placing) as the page's busy state `busy`:
 * the progress text says `text`, a failure shows its error and `failText`. Resolves to success.
 */
async function runTask(busy, text, failText, task) {
  app.busy = busy;
  clearError();
  setPageState('loading');
  setProgressText(text, 0);
  updateButtons();
  try {
    await task();
    setPageState('ready');
    return true;
  } catch (err) {
    showError(err);
    setProgressText(failText, 0);
    setPageState('error');
    return false;
  } finally {
    app.busy = null;
    updateButtons();
  }
}

/** Show a freshly placed mesh: its figures, the model in the viewer, no result. */
async function showPlacedModel(name, info, mesh, frame) {
  showInfo(name, info);
  clearReport();
  await setPreview(null);
  if (app.viewer) {
    app.viewer.setModel(mesh, { filledFrom: info && info.repair ? info.repair.first_filled_face : undefined });
    if (frame) app.viewer.frame();
  }
}

/** Load mesh bytes; on failure the previous model stays loaded. Returns true on success. */
async function loadBytes(name, bytes, { frame = true } = {}) {
  if (!app.slicer) return false;
  if (app.busy === 'slicing') cancelSlice();
  while (app.busy) await nextFrame();
  return runTask('loading', `reading ${name}`, `could not load ${name}`, async () => {
    // The facade keeps its own copy of the bytes (it re-sends them to a respawned worker).
    const { meshId, info, mesh } = await app.slicer.loadMesh(name, bytes, app.model.toPlacement());
    const previous = app.mesh;
    app.mesh = { name, meshId, info };
    if (previous && typeof app.slicer.unloadMesh === 'function') app.slicer.unloadMesh(previous.meshId).catch(() => {});
    app.placementDirty = false;
    await showPlacedModel(name, info, mesh, frame);
    setProgressText(`loaded ${name}: press Slice`, 0);
  });
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
 * Run one slice request with the page's progress, cancel and error handling: the progress text
 * starts at `startText`; onResult(result, started) shows the result; a failure shows its error,
 * 'cancelled', or the text onFailure(err, started) resolves to (else `failText`). marked:
 * performance marks 'omnislice:slice-start' and 'omnislice:result' for the tests' long-task check.
 */
async function runSlice(settings, { startText, failText, onResult, onFailure = () => {}, marked = false }) {
  if (!app.slicer || !app.mesh || app.busy) return;
  app.busy = 'slicing';
  app.abort = new AbortController();
  app.progress = newProgress(methodNamed(app.model.get('method')).data.stageWeights);
  $('stage-list').replaceChildren();
  clearError();
  setPageState('slicing');
  setProgressText(startText, 0);
  updateButtons();
  const started = performance.now();
  if (marked) performance.mark('omnislice:slice-start');
  try {
    const result = await app.slicer.slice(app.mesh.meshId, settings, { onProgress, signal: app.abort.signal });
    if (marked) performance.mark('omnislice:result');
    await onResult(result, started);
  } catch (err) {
    const cancelled = err && err.code === 'cancelled';
    let text = '';
    try {
      text = await onFailure(err, started);
    } catch (failed) {
      // The slice's own error is what the user must read; a failure to show more is secondary.
      console.error('showing the failed slice:', failed);
    }
    showError(err);
    setProgressText(cancelled ? 'cancelled' : text || failText, 0);
    setPageState(cancelled ? 'cancelled' : 'error');
  } finally {
    app.busy = null;
    app.abort = null;
    updateButtons();
  }
}

/** Slice the loaded mesh with the panel's settings and show the result. */
function slice() {
  const settings = app.model.toSliceSettings();
  return runSlice(settings, {
    startText: 'starting',
    failText: 'slicing failed',
    marked: true,
    async onFailure(err, started) {
      sliceFailed(app, app.progress);
      if (!(err && err.code === 'unsound_program' && err.report)) return '';
      // What the refused slice measured stays on show: figures, model, views; no program.
      const { report, info, preview, mesh } = err;
      await showResult({ report, info, preview, mesh }, started, { refused: true });
      return `refused after ${((performance.now() - started) / 1000).toFixed(2)} s: not sound, no program written`;
    },
    async onResult(result, started) {
      await showResult(result, started);
      app.resultSettings = settings;
    },
  });
}

/**
 * Show a slice result: report, model, views, machine view; the summary line and the page state
 * 'done' last. Each step is its own task, so none of them holds the main thread for long.
 * refused: a refused slice's measures (no program): shown as app.refused, the caller reports the
 * failure (no 'done', no slice counted).
 */
async function showResult(result, started, { refused = false } = {}) {
  app.busy = 'showing';
  await nextFrame();
  timed('show-report', () => {
    resetPanels(app);
    app.result = refused ? null : result;
    app.refused = refused ? result : null;
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
  if ($('machine-toggle').checked) timed('machine-view', () => openMachineView(app));
  if (refused) return;
  app.sliceCount += 1;
  document.body.dataset.sliceCount = String(app.sliceCount);
  const wall = ((performance.now() - started) / 1000).toFixed(2);
  const summary = doneSummary(result.report);
  setProgressText(`done in ${wall} s${summary ? `: ${summary}` : ''}`, 1);
  showStages(app.progress, { finished: true });
  setPageState('done');
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
  downloadBlob(new Blob([app.result.programBytes], { type: PROGRAM_KINDS[extension].mime }),
    programFileName(app.mesh ? app.mesh.name : 'model', extension));
}

// ---- placement edits ----------------------------------------------------------------------

function onSettingChange(event) {
  if (!isPlacementKey(event.detail.key) || !app.mesh) return;
  app.placementDirty = true;
  // Place again after a short pause so the model shows the new placement; if the engine is busy,
  // the next slice applies it (slice() sends the placement keys too).
  clearTimeout(app.placeTimer);
  app.placeTimer = setTimeout(() => {
    if (!app.busy && app.mesh && app.placementDirty) applyPlacement();
  }, 250);
}

/** Show the loaded mesh with the current placement (the old tool-paths no longer match it). */
function applyPlacement() {
  return runTask('placing', `placing ${app.mesh.name}`, 'placement failed', async () => {
    const { info, mesh } = await app.slicer.info(app.mesh.meshId, app.model.toPlacement());
    app.placementDirty = false;
    await showPlacedModel(app.mesh.name, info, mesh, true);
    setProgressText(`placed ${app.mesh.name}: press Slice`, 0);
  });
}

// ---- start-up -----------------------------------------------------------------------------------

/** The controls that need no settings, once at load. */
function wireUi() {
  onFileChosen($('file-input'), loadFile);
  $('slice-button').addEventListener('click', () => slice());
  $('demo-model').addEventListener('change', (e) => {
    const demo = DEMOS[e.target.value];
    e.target.value = '';
    if (demo) loadDemo(demo, { sliceAfter: true });
  });
  $('cancel-button').addEventListener('click', () => cancelSlice());
  $('download-program').addEventListener('click', () => download());
  // Before the methods' own listeners on the sliders (wirePanels), which follow the new range.
  $('layer-min-slider').addEventListener('input', (e) => applyLayerRange(e.target));
  $('layer-slider').addEventListener('input', (e) => applyLayerRange(e.target));
  $('show-model').addEventListener('change', (e) => app.viewer && app.viewer.setModelVisible(e.target.checked));
  wirePanels(app);
  showReport(null);
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

/** The settings panel and what follows the settings, once the model exists (start()). */
function wireSettings() {
  createSettingsPanel(document.getElementById('settings-panel'), app.model, app.history,
    { groupHosts: { Machine: document.getElementById('machine-fields') } });
  app.model.addEventListener('change', onSettingChange);
  wireMachinePanel(app);
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
    if (demo.tilt && !TILT_KINDS.includes(selectedMachineKind(app.model.values))) {
      if (app.model.get('machine_json')) app.history.execute(new SetSettingCommand(app.model, 'machine_json', ''));
      app.history.execute(new SetSettingCommand(app.model, 'machine', demo.tilt));
    }
    if (await loadBytes(demo.name, bytes) && sliceAfter) await slice();
  } catch (err) {
    showError(err);
    setPageState('error');
  }
}

async function start() {
  wireUi();
  createViewer();
  setPageState('starting');
  updateButtons();
  let slicer = null;
  try {
    // Imported here, not statically, so the page still reports the problem if the engine cannot
    // load.
    const { createSlicer } = await import('/workers/engine.js');
    slicer = await createSlicer();
    // The settings' defaults, ranges and choices are the core's table, so the model (and the
    // panels over it) can only be made once the engine runs; settingsFields throws on drift.
    app.model = new SettingsModel(settingsFields(await slicer.settingsSchema()));
  } catch (err) {
    if (slicer) slicer.dispose();
    showError({ code: err.code || 'engine_unavailable', message: `the slicing engine did not start: ${err.message}` });
    setProgressText('engine unavailable', 0);
    setPageState('error');
    return;
  }
  app.slicer = slicer;
  wireSettings();
  updateButtons();
  await loadDemo(demoOfQuery(location.search), { sliceAfter: true });
}

installPageApi(app);
// The service worker (web/sw.js) keeps the app, its engine and the demos for offline use. Not
// registered from a file: URL; refused registrations (a browser without workers, a blocked
// context) leave the page as it is.
if ('serviceWorker' in navigator && /^https?:$/.test(location.protocol)) {
  navigator.serviceWorker.register('/sw.js').catch(() => {});
}
start();
