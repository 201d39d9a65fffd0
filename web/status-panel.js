// SPDX-License-Identifier: MIT
// The page's status: its state on <body data-state> (starting, loading, ready, slicing, done,
// error, cancelled; the end-to-end tests wait on it), the progress bar and its text, the list of
// stages under it, and the error line. The progress of one slice is a plain object (newProgress):
// the method's stage weights, every stage seen with its times, and the search levels a multidir
// decomposition reports; recordProgress keeps it, the DOM functions draw it.
import { byTestId as $ } from './panel-dom.js';

/** Mirror the page state on <body data-state>. */
export function setPageState(state) {
  document.body.dataset.state = state;
}

/** Show an error ({code, message} or anything thrown) as 'code: message'; 'cancelled' as a notice. */
export function showError(err) {
  const el = $('error-message');
  const code = (err && err.code) || 'internal';
  const message = (err && err.message) || String(err);
  el.textContent = `${code}: ${message}`;
  el.dataset.code = code;
  el.classList.toggle('notice', code === 'cancelled');
  el.hidden = false;
}

export function clearError() {
  const el = $('error-message');
  el.hidden = true;
  el.textContent = '';
  delete el.dataset.code;
}

/** The progress text, and the bar's value when a fraction is given. */
export function setProgressText(text, fraction) {
  $('progress-text').textContent = text;
  const bar = $('progress');
  // The bar carries the stage text too (accessible name and fallback content).
  bar.textContent = text;
  bar.setAttribute('aria-valuetext', text);
  if (fraction !== undefined) bar.value = fraction;
}

/**
 * Overall progress (0..1) of `stage` at `fraction` for a method's stage weights: the weights of the
 * stages before it plus its share; null for a stage the method does not list.
 */
export function overallProgress(weights, stage, fraction) {
  const names = Object.keys(weights);
  const k = names.indexOf(stage);
  if (k < 0) return null;
  let before = 0;
  for (let i = 0; i < k; i++) before += weights[names[i]];
  const f = Math.min(Math.max(Number(fraction) || 0, 0), 1);
  return Math.min(1, before + weights[stage] * f);
}

/** Progress state of one slice with the method's stage weights ({stage: share of the bar}). */
export function newProgress(weights) {
  return {
    stage: '', fraction: 0, overall: 0, pending: false,
    weights,
    stages: new Map(),  // stage -> {fraction, start, end (performance.now() ms), detail}, in arrival order
    levels: [],         // progress.search of every search-level event, in arrival order
    levelsDrawn: 0,     // levels shown by the live J_G chart
    liveDraws: [],      // the live chart's values at each drawing (for the tests)
  };
}

/**
 * Keep one progress event ({stage, fraction, search?, candidate?}) in `p`: a new stage ends the
 * previous ones (of its candidate, with method = auto in a pool of workers); a search level (progress.search) is kept and becomes its stage's detail text
 * (describeSearch(search)).
 */
export function recordProgress(p, { stage, fraction, search, candidate }, { now = performance.now(), describeSearch = () => '' } = {}) {
  // method = auto's candidates run side by side in a pool of workers: each one's stages are its
  // own entries ("voxel · growth"), and a new stage ends only the earlier ones of its candidate.
  const key = candidate ? `${candidate} · ${stage}` : stage;
  p.stage = key;
  p.fraction = Math.min(Math.max(Number(fraction) || 0, 0), 1);
  const overall = overallProgress(p.weights, stage, p.fraction);
  if (overall !== null) p.overall = Math.max(p.overall, overall);
  let entry = p.stages.get(key);
  if (!entry) {
    for (const e of p.stages.values()) if (e.candidate === candidate) e.fraction = 1;
    entry = { fraction: 0, start: now, end: now, candidate };
    p.stages.set(key, entry);
  }
  entry.fraction = Math.max(entry.fraction, p.fraction);
  entry.end = now;
  if (search) {
    p.levels.push(search);
    entry.detail = describeSearch(search);
  }
}

/** The progress text of `p`'s latest event: 'stage 42% — detail'. */
export function progressText(p) {
  const detail = p.stages.get(p.stage)?.detail;
  return `${p.stage} ${Math.round(p.fraction * 100)}%${detail ? ` — ${detail}` : ''}`;
}

/**
 * The stages of `p` in arrival order: [stage, entry, ms]. A stage lasts from its first report to
 * the next stage's first report (the last one to its own last report).
 */
export function stageTimes(p) {
  const list = [...p.stages];
  return list.map(([stage, e], i) => {
    // The next stage of the same candidate (method = auto in a pool: candidates run side by side).
    const next = list.slice(i + 1).find(([, f]) => f.candidate === e.candidate);
    return [stage, e, (next ? next[1].start : e.end) - e.start];
  });
}

/** The stage list under the progress bar: name, percentage and time of every stage seen. */
export function showStages(p, { finished = false } = {}) {
  const times = stageTimes(p);
  const items = times.map(([stage, e, dt], k) => {
    const li = document.createElement('li');
    li.dataset.stage = stage;
    const done = finished || e.fraction >= 1 || times.slice(k + 1).some(([, f]) => f.candidate === e.candidate);
    li.className = done ? 'done' : 'running';
    const name = document.createElement('span');
    name.textContent = stage;
    const pct = document.createElement('span');
    pct.className = 'pct';
    pct.textContent = `${Math.round((done ? 1 : e.fraction) * 100)}%`;
    const ms = document.createElement('span');
    ms.className = 'ms';
    ms.textContent = dt >= 1000 ? `${(dt / 1000).toFixed(1)} s` : `${Math.round(dt)} ms`;
    li.append(name, pct, ms);
    if (e.detail) {
      const detail = document.createElement('span');
      detail.className = 'detail';
      detail.textContent = e.detail;
      li.append(detail);
    }
    return li;
  });
  $('stage-list').replaceChildren(...items);
}
