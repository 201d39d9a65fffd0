// SPDX-License-Identifier: MIT
// Pure data of method = auto's page (issue 28 item 1): the core ran every method the machine
// takes, checked each program by simulation and delivered the best (report.auto: candidates,
// chosen, reason). The delivered result is the chosen method's: its own sections and views show
// as when it is chosen by hand; this adds the candidates side by side. No DOM; unit-tested in Node.
import { formatSeconds } from '../format.js';

/** Progress of an auto slice: the stage 'auto' moves once per candidate (each candidate's own
 *  stages show in the stage list as they come). */
export const AUTO_STAGE_WEIGHTS = Object.freeze({ auto: 1 });

/** report.auto, or null. */
export function autoSection(report) {
  const a = report && report.auto;
  return a && Array.isArray(a.candidates) ? a : null;
}

/**
 * One row per candidate in the order they ran: {method, state, verdict, supported, collisions,
 * support, time, ms}. state: 'chosen' | 'sound' | 'unsound' | 'stopped' (stopped before its
 * check: it could not win) | 'failed' (no program: the message says why).
 */
export function candidateRows(section) {
  if (!section) return [];
  return section.candidates.map((c) => {
    const v = c.verify;
    let state = 'failed';
    if (c.method === section.chosen) state = 'chosen';
    else if (c.stopped_early) state = 'stopped';
    else if (c.status === 'ok' && v) state = v.sound ? 'sound' : 'unsound';
    let verdict = c.message || c.status;
    if (c.status === 'ok' && v) verdict = v.sound ? 'sound' : (v.failures && v.failures[0]) || 'unsound';
    if (c.stopped_early) verdict = 'stopped: could not win';
    const ok = c.status === 'ok' || c.stopped_early;
    return {
      method: c.method,
      state,
      verdict,
      supported: v && Number.isFinite(v.supported) ? v.supported.toFixed(3) : '—',
      collisions: v && Number.isFinite(v.collisions) ? String(v.collisions) : '—',
      support: ok && Number.isFinite(c.support_volume_mm3) ? `${Math.round(c.support_volume_mm3)} mm³` : '—',
      time: ok && c.estimated_time_s > 0 ? formatSeconds(c.estimated_time_s) : '—',
      ms: c.timings_ms && Number.isFinite(c.timings_ms.total) ? `${(c.timings_ms.total / 1000).toFixed(1)} s` : '—',
    };
  });
}

/** Rows [key, label, text] of the choice: which method, and why. */
export function autoSummaryRows(section) {
  if (!section) return [];
  return [
    ['chosen', 'chosen', section.chosen || '—'],
    ['reason', 'why', section.reason || '—'],
  ];
}

/** The line after 'done in … s: '. */
export function autoDoneSummary(section) {
  return section && section.chosen ? `auto chose ${section.chosen} of ${section.candidates.length}` : '';
}
