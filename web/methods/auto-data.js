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

/**
 * A small picture of a candidate's program for the candidates table: its extruding segments
 * (preview.positions, part frame; travel left out) seen from the front right and a little above,
 * fitted into width x height pixels (y down, 2 px margin), at most maxSegments of them (every
 * k-th); and where its check found it fails (preview.unsupportedPoints, collisionPoints), in the
 * same projection. Returns {lines: Float32Array (x0 y0 x1 y1 per line), features: Uint8Array,
 * unsupported: Float32Array (x y), collisions: Float32Array (x y)}, or null without segments.
 */
export function thumbnailLines(preview, width, height, maxSegments = 6000) {
  const pos = preview && preview.positions;
  const feat = preview && preview.features;
  if (!pos || !feat || !(width > 4 && height > 4)) return null;
  const n = Math.min(feat.length, Math.floor(pos.length / 6));
  const c = Math.SQRT1_2;
  const pu = (x, y) => (x - y) * c;
  const pv = (x, y, z) => z + (x + y) * c * 0.5;
  let uMin = Infinity, uMax = -Infinity, vMin = Infinity, vMax = -Infinity, printed = 0;
  for (let s = 0; s < n; s++) {
    if (feat[s] === 0) continue;
    ++printed;
    for (let e = 0; e < 2; e++) {
      const o = 6 * s + 3 * e;
      const u = pu(pos[o], pos[o + 1]), v = pv(pos[o], pos[o + 1], pos[o + 2]);
      if (u < uMin) uMin = u;
      if (u > uMax) uMax = u;
      if (v < vMin) vMin = v;
      if (v > vMax) vMax = v;
    }
  }
  if (!printed) return null;
  const scale = Math.min((width - 4) / Math.max(uMax - uMin, 1e-9), (height - 4) / Math.max(vMax - vMin, 1e-9));
  const u0 = (width - scale * (uMax - uMin)) / 2, v0 = (height - scale * (vMax - vMin)) / 2;
  const px = (x, y) => u0 + scale * (pu(x, y) - uMin);
  const py = (x, y, z) => height - v0 - scale * (pv(x, y, z) - vMin);
  const step = Math.max(1, Math.ceil(printed / maxSegments));
  const lines = new Float32Array(4 * Math.ceil(printed / step));
  const features = new Uint8Array(lines.length / 4);
  let k = 0, seen = 0;
  for (let s = 0; s < n; s++) {
    if (feat[s] === 0 || seen++ % step !== 0) continue;
    const o = 6 * s;
    lines.set([px(pos[o], pos[o + 1]), py(pos[o], pos[o + 1], pos[o + 2]),
      px(pos[o + 3], pos[o + 4]), py(pos[o + 3], pos[o + 4], pos[o + 5])], 4 * k);
    features[k++] = feat[s];
  }
  const points = (xyz) => {
    const m = xyz ? Math.floor(xyz.length / 3) : 0;
    const out = new Float32Array(2 * m);
    for (let i = 0; i < m; i++) {
      out[2 * i] = px(xyz[3 * i], xyz[3 * i + 1]);
      out[2 * i + 1] = py(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
    }
    return out;
  };
  return {
    lines: lines.subarray(0, 4 * k), features: features.subarray(0, k),
    unsupported: points(preview.unsupportedPoints), collisions: points(preview.collisionPoints),
  };
}
