// SPDX-License-Identifier: MIT
// The machine side of the page: the machine panel (built-in machine or a user's profile file,
// checked by the core; the profile in use and what the chosen method lacks on it), the motion
// figures of the report, a program file replayed through its declared machine, and the machine
// animation (MachineView: the articulated machine moving the part, driven by preview.machine,
// with a step slider and play/pause). State lives in the app state: app.machineView, app.replay,
// app.machinePlay, app.machineFiles.
import { figure } from './format.js';
import { MACHINE_KINDS, machineAxisNames } from './machine-kinematics.js';
import { MachineView } from './machine-view.js';
import { machineHint } from './methods/index.js';
import { byTestId as $, downloadBlob, onFileChosen } from './panel-dom.js';
import { selectedMachineKind } from './settings-fields.js';
import { SetSettingCommand } from './settings-panel.js';
import { clearError, showError } from './status-panel.js';

const MOTION_KEYS = ['samples', 'subdivisions', 'filtered_orientations', 'feed_limited_moves', 'safe_rotations',
  'max_joint_step', 'pose_cost', 'min_singularity'];

/** The report's motion figures (hidden without report.motion). */
export function showMotion(report) {
  const r = report || {};
  const motion = r.motion && typeof r.motion === 'object' ? r.motion : null;
  $('report-motion').hidden = !motion;
  // Angular figures are radians for a robot's joints, degrees for the A, B, C axes.
  const unit = r.machine_kind === 'robot6' ? ' rad' : '°';
  for (const key of MOTION_KEYS) {
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

/** The machine panel follows the settings: which profile is used, the built-in select's state. */
export function showMachineProfile(app) {
  const json = app.model.get('machine_json');
  const fromFile = !!json;
  $('machine').disabled = fromFile;
  $('machine-builtin').hidden = !fromFile;
  const kind = selectedMachineKind(app.model.values);
  $('machine-profile').textContent = fromFile
    ? `profile ${app.machineFiles.get(json) || 'from a file'} (${kind})`
    : `built-in profile ${app.model.get('machine')}`;
  $('machine-profile').dataset.kind = kind;
  const hint = machineHint(app.model.get('method'), kind);
  $('method-hint').hidden = !hint;
  $('method-hint').textContent = hint;
}

/** Load a user's machine profile: the core checks it; errors show with their code. */
async function loadMachineFile(app, file) {
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
    if (!MACHINE_KINDS.includes(kind)) {
      throw { code: 'invalid_option', message: `machine JSON: unknown kind "${kind}" (${MACHINE_KINDS.join(', ')})` };
    }
    app.machineFiles.set(json, file.name);
    app.history.execute(new SetSettingCommand(app.model, 'machine_json', json));
  } catch (err) {
    showError({ code: (err && err.code) || 'parse_error', message: `${file.name}: ${(err && err.message) || err}` });
  }
}

/** Replay a program file (G-code, robot CSV, URScript) through its declared machine, animated. */
async function replayProgramFile(app, file) {
  if (!file || !app.slicer || app.busy) return;
  clearError();
  try {
    const text = await file.text();
    const r = await app.slicer.replay(text);
    app.replay = { name: file.name, profile: r.profile, preview: r.preview };
    $('machine-toggle').checked = true;
    app.actions.updateButtons();
    openMachineView(app);
  } catch (err) {
    showError({ code: (err && err.code) || 'io_error', message: `${file.name}: ${(err && err.message) || err}` });
  }
}

/** Download the selected built-in profile as JSON (a template for a user's own profile file). */
async function saveBuiltinProfile(app) {
  if (!app.slicer) return;
  try {
    const name = app.model.get('machine');
    const list = await app.slicer.machines({ nozzle: app.model.get('nozzle') });
    const found = list.find((x) => x.name === name);
    if (!found) throw { code: 'invalid_option', message: `no built-in machine ${name}` };
    downloadBlob(new Blob([`${JSON.stringify(found.profile, null, 2)}\n`], { type: 'application/json' }), `${name}.json`);
  } catch (err) {
    showError(err);
  }
}

/**
 * Build the machine view of the replayed program, else of the current result, and show it in
 * place of the part view.
 */
export function openMachineView(app) {
  closeMachineView(app);
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
  showMachineStep(app, app.machineView.stepCount - 1);
}

export function closeMachineView(app) {
  stopMachinePlay(app);
  if (app.machineView) {
    if (app.viewer) app.viewer.setMachine(null);
    app.machineView.dispose();
    app.machineView = null;
  }
  $('machine-bar').hidden = true;
  delete $('machine-step').dataset.tipError;
}

/** Pose the machine at move s; the texts and data-tip-error (mm) follow. */
function showMachineStep(app, s) {
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

function stopMachinePlay(app) {
  if (app.machinePlay) cancelAnimationFrame(app.machinePlay);
  app.machinePlay = 0;
  $('machine-play').textContent = '▶';
  $('machine-play').setAttribute('aria-pressed', 'false');
}

/** Play from the current move (from the start when at the end); about 20 s for a whole program. */
function toggleMachinePlay(app) {
  const view = app.machineView;
  if (!view) return;
  if (app.machinePlay) {
    stopMachinePlay(app);
    return;
  }
  let step = view.step >= view.stepCount - 1 ? 0 : view.step;
  const perFrame = Math.max(1, Math.round(view.stepCount / (20 * 60)));
  $('machine-play').textContent = '❚❚';
  $('machine-play').setAttribute('aria-pressed', 'true');
  const tick = () => {
    step = Math.min(step + perFrame, view.stepCount - 1);
    showMachineStep(app, step);
    if (step >= view.stepCount - 1 || app.machineView !== view) {
      stopMachinePlay(app);
      return;
    }
    app.machinePlay = requestAnimationFrame(tick);
  };
  app.machinePlay = requestAnimationFrame(tick);
}

/** The machine panel's and the machine bar's controls, once at start-up. */
export function wireMachinePanel(app) {
  app.model.addEventListener('change', () => showMachineProfile(app));
  showMachineProfile(app);
  onFileChosen($('machine-file'), (file) => loadMachineFile(app, file));
  $('machine-save').addEventListener('click', () => saveBuiltinProfile(app));
  onFileChosen($('program-file'), (file) => replayProgramFile(app, file));
  $('machine-builtin').addEventListener('click', () => {
    app.history.execute(new SetSettingCommand(app.model, 'machine_json', ''));
  });
  $('machine-toggle').addEventListener('change', (e) => {
    if (e.target.checked) openMachineView(app);
    else closeMachineView(app);
  });
  $('machine-step').addEventListener('input', (e) => {
    stopMachinePlay(app);
    showMachineStep(app, Number(e.target.value));
  });
  $('machine-play').addEventListener('click', () => toggleMachinePlay(app));
}
