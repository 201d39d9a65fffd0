// SPDX-License-Identifier: MIT
// Pure data preparation for the iso-planar view (paper 003; no three.js, no DOM; unit-tested in
// Node):
//   - the polar plot of the material deposition rate v_e(theta) from report.isoplanar.curve
//     ([[theta_deg, v_e], ...], theta in [0, 180)): a drive plane at theta is the same plane as at
//     theta + 180, so the curve is drawn closed over 0..360 by that symmetry, with round rings,
//     the direction theta* marked as a line through the centre and dots on the curve;
//   - the angle of a point clicked on the plot (folded into [0, 180)) and v_e there (periodic
//     linear interpolation);
//   - the colours of the NL curves (preview.curves, 1-based, 0 = none): adjacent curves alternate
//     between two contrasting colours so the side steps show;
//   - the figures of report.isoplanar and the comparison table of two runs (the searched theta*
//     and a chosen direction) with the benchmark means.

import { figure, formatMs, formatSeconds, withUnit } from '../format.js';

/**
 * Progress stages of a surface-method slice (paper 003), in pipeline order, with their share of
 * the bar (sums to 1): the base by planar layers, then the iso-planar stages of the surface layer
 * (feed field, drive-direction search, paths, benchmark over all directions).
 */
export const SURFACE_STAGE_WEIGHTS = Object.freeze({
  read: 0.02, validate: 0.03, place: 0.01, slice: 0.04, toolpath: 0.08, feed: 0.2, direction: 0.15,
  paths: 0.12, benchmark: 0.2, motion: 0.1, program: 0.05,
});

/** Degrees -> radians. */
const RAD = Math.PI / 180;

/** theta folded into [0, 180) (a drive plane and its opposite are one plane). */
export function foldTheta(theta) {
  const t = Number(theta) % 180;
  const f = t < 0 ? t + 180 : t;
  return f >= 180 ? 0 : f;
}

/**
 * Check and sort report.isoplanar.curve: [[theta_deg, v_e], ...] with theta in [0, 180) and
 * v_e >= 0, all finite; returned sorted by theta.
 * @throws Error naming the first bad entry
 */
export function readCurve(curve) {
  if (!Array.isArray(curve)) throw new Error('curve: not an array of [theta_deg, v_e] pairs');
  const out = [];
  curve.forEach((p, i) => {
    if (!Array.isArray(p) || p.length < 2) throw new Error(`curve[${i}]: not a [theta_deg, v_e] pair`);
    const theta = Number(p[0]);
    const v = Number(p[1]);
    if (!Number.isFinite(theta) || theta < 0 || theta >= 180) throw new Error(`curve[${i}]: theta ${p[0]} outside [0, 180)`);
    if (!Number.isFinite(v) || v < 0) throw new Error(`curve[${i}]: v_e ${p[1]} is not a non-negative number`);
    out.push([theta, v]);
  });
  out.sort((a, b) => a[0] - b[0]);
  return out;
}

/**
 * v_e at theta (degrees, any value: folded into [0, 180)) by linear interpolation between the
 * sorted samples, periodic over 180 degrees; NaN without samples.
 */
export function curveValueAt(sorted, theta) {
  const n = sorted.length;
  if (n === 0) return NaN;
  if (n === 1) return sorted[0][1];
  const t = foldTheta(theta);
  let k = 0;
  while (k < n && sorted[k][0] <= t) k++;
  // Neighbours (wrapping over 180): the last sample at or before t and the first after it.
  const a = k === 0 ? [sorted[n - 1][0] - 180, sorted[n - 1][1]] : sorted[k - 1];
  const b = k === n ? [sorted[0][0] + 180, sorted[0][1]] : sorted[k];
  const span = b[0] - a[0];
  if (!(span > 0)) return a[1];
  return a[1] + ((t - a[0]) / span) * (b[1] - a[1]);
}

/** Round ring values (1, 2 or 5 times a power of ten apart) up to about vMax: at most `count`. */
export function ringValues(vMax, count = 4) {
  if (!(vMax > 0) || !Number.isFinite(vMax)) return [];
  const rough = vMax / Math.max(count, 1);
  const p10 = 10 ** Math.floor(Math.log10(rough));
  const step = [1, 2, 5, 10].map((m) => m * p10).find((x) => x >= rough * 0.999) || 10 * p10;
  const out = [];
  for (let j = 1; j * step <= vMax * (1 + 1e-9); j++) out.push(Number((j * step).toPrecision(12)));
  return out;
}

/** SVG point of (theta degrees, value) on a plot centred at (cx, cy) with scale px per unit (y up). */
export function polarPoint(theta, value, { cx, cy, scale }) {
  return [cx + value * scale * Math.cos(theta * RAD), cy - value * scale * Math.sin(theta * RAD)];
}

/**
 * Geometry of the polar plot of v_e(theta) in a size x size box (SVG units, y down; theta counted
 * counter-clockwise from +x, as the drive-plane direction in the XY plane is).
 * @param {Array} curve report.isoplanar.curve
 * @param {{size?: number, pad?: number, thetaStar?: number, valueStar?: number, extra?: number[]}} [o]
 *   thetaStar: report.isoplanar.theta_deg (default: the argmax of the samples); valueStar: v_e
 *   there (default: interpolated); extra: other marked directions (e.g. a compared theta)
 * @returns {{cx, cy, radius, scale, vMax, vMin, samples: number, points: number[][], path: string,
 *   rings: {value, r}[], star: {theta, value, line: number[][], dots: number[][]},
 *   best: {theta, value}, marks: {theta, value, line, dots}[]}} points: the closed curve, the
 *   samples at theta then at theta + 180 (2 x samples points); vMax, best: the sampled maximum;
 *   the outer ring covers it and v_e(theta*)
 * @throws Error when the curve is malformed or empty
 */
export function polarPlotGeometry(curve, { size = 220, pad = 14, thetaStar, valueStar, extra = [] } = {}) {
  const sorted = readCurve(curve);
  if (sorted.length === 0) throw new Error('curve: no samples');
  let best = sorted[0];
  let vMin = Infinity;
  for (const p of sorted) {
    if (p[1] > best[1]) best = p;
    if (p[1] < vMin) vMin = p[1];
  }
  const cx = size / 2;
  const cy = size / 2;
  const radius = size / 2 - pad;
  // The reported v_e(theta*) may lie between samples, above the sampled maximum.
  const starValue = Number(valueStar);
  const peak = Math.max(best[1], Number.isFinite(starValue) ? starValue : 0);
  const rings = ringValues(peak);
  // The outer ring (when it is above the maximum) sets the scale, so the curve stays inside it.
  const top = Math.max(peak, rings.length ? rings[rings.length - 1] : 0);
  const vMax = best[1];
  const scale = top > 0 ? radius / top : 0;
  const frame = { cx, cy, scale };
  const points = [];
  for (const half of [0, 180]) for (const [t, v] of sorted) points.push(polarPoint(t + half, v, frame));
  const path = `${points.map((p, i) => `${i ? 'L' : 'M'}${p[0].toFixed(2)} ${p[1].toFixed(2)}`).join(' ')} Z`;
  const mark = (theta, value) => {
    const t = foldTheta(theta);
    const v = Number.isFinite(value) ? value : curveValueAt(sorted, t);
    return {
      theta: t,
      value: v,
      line: [polarPoint(t, top, frame), polarPoint(t + 180, top, frame)],
      dots: [polarPoint(t, v, frame), polarPoint(t + 180, v, frame)],
    };
  };
  const hasStar = Number.isFinite(Number(thetaStar)) && Number(thetaStar) >= 0;
  const star = hasStar ? mark(Number(thetaStar), starValue) : mark(best[0], best[1]);
  return {
    cx, cy, radius, scale, vMax, vMin, samples: sorted.length, points, path,
    rings: rings.map((value) => ({ value, r: value * scale })),
    star,
    best: { theta: best[0], value: best[1] },
    marks: extra.filter((t) => Number.isFinite(Number(t))).map((t) => mark(Number(t))),
  };
}

/**
 * The drive-plane direction (degrees in [0, 180), rounded to `step`) of a point (x, y) on the
 * plot centred at (cx, cy); null at the centre.
 */
export function thetaFromPlotPoint(x, y, cx, cy, step = 1) {
  const dx = x - cx;
  const dy = cy - y;
  if (Math.hypot(dx, dy) < 1e-9) return null;
  const deg = Math.atan2(dy, dx) / RAD;
  const rounded = Math.round(foldTheta(deg) / step) * step;
  return foldTheta(Number(rounded.toFixed(6)));
}

/**
 * The two colours of adjacent NL curves (0..255 RGB): odd curves orange, even curves near-white
 * (apart from every feature colour of the preview's palette, and from each other in lightness).
 */
export const CURVE_COLORS = [[0xff, 0x8a, 0x1f], [0xee, 0xf2, 0xff]];

/** Colour of NL curve c (1-based; 0 = none -> null). */
export function curveColor(c) {
  return c > 0 ? CURVE_COLORS[(c - 1) % 2] : null;
}

/**
 * Statistics of preview.curves (#S, 1-based NL curve index, 0 = none): how many curves (the
 * highest index), how many segments lie on one, and whether indices never decrease along the print
 * order (curves are numbered in print order).
 */
export function curveStats(curves) {
  const S = curves ? curves.length : 0;
  let count = 0;
  let onCurves = 0;
  let ordered = true;
  let last = 0;
  for (let s = 0; s < S; s++) {
    const c = curves[s];
    if (c === 0) continue;
    onCurves++;
    if (c > count) count = c;
    if (c < last) ordered = false;
    last = c;
  }
  return { segments: S, onCurves, count, ordered };
}

/** True when the preview carries NL curve indices (the iso-planar fill ran). */
export function hasCurves(preview) {
  return !!(preview && preview.curves && preview.curves.length > 0
    && preview.features && preview.curves.length === preview.features.length);
}

/** The side step range 'min–max mm' of report.isoplanar.side_step_mm, or '—'. */
export function sideStepText(iso) {
  const s = iso && iso.side_step_mm;
  if (!s || !Number.isFinite(s.min) || !Number.isFinite(s.max)) return '—';
  return `${figure(s.min)}–${figure(s.max)} mm`;
}

/**
 * Summary rows [key, label, text] of report.isoplanar (keys double as data-testid suffixes:
 * iso-<key>), in display order; absent figures show '—'.
 */
export function isoplanarSummaryRows(iso) {
  const r = iso && typeof iso === 'object' ? iso : {};
  const b = r.benchmark && typeof r.benchmark === 'object' ? r.benchmark : {};
  const t = r.timings_ms && typeof r.timings_ms === 'object' ? r.timings_ms : {};
  return [
    ['theta', r.forced ? 'θ (forced)' : 'θ* (searched)', Number.isFinite(r.theta_deg) ? `${figure(r.theta_deg)}°` : '—'],
    ['deposition_rate', 'deposition rate v_e', withUnit(r.deposition_rate_mm3_s, 'mm³/s')],
    ['side_step', 'side step (min–max)', sideStepText(r)],
    ['mean_width', 'mean printing width', withUnit(r.mean_width_mm, 'mm')],
    ['mean_feed', 'mean feed rate', withUnit(r.mean_feed_mm_s, 'mm/s')],
    ['planes', 'drive planes', figure(r.planes)],
    ...(r.curves !== undefined ? [['curves', 'NL curves', figure(r.curves)]] : []),
    ...(r.paths !== undefined ? [['paths', 'zig-zag paths', figure(r.paths)]] : []),
    ['path', 'path length', withUnit(r.path_mm, 'mm')],
    ['time', 'estimated time', formatSeconds(r.estimated_time_s)],
    ['directions', 'directions searched', figure(b.directions)],
    ['samples', 'surface samples', figure(r.samples)],
    ['unreachable', 'unreachable samples', figure(r.unreachable)],
    ...Object.keys(t).filter((k) => Number.isFinite(t[k])).map((k) => [`time_${k}`, `time: ${k}`, formatMs(t[k])]),
  ];
}

/**
 * Rows of the comparison table: one per run ({label, report}: a slice report with .isoplanar),
 * then the benchmark means of the first run's report (mean estimated time and path length over
 * all directions). Each row: {key, label, theta, time, path, rate, timeDelta, pathDelta} with
 * time in s, path in mm, rate in mm³/s (NaN when absent) and the deltas relative to the first
 * row (fractions; 0 for the first row). A run's time and path are report.isoplanar's (the
 * iso-planar paths) when given, else the whole program's.
 */
export function comparisonRows(runs) {
  const rows = [];
  const num = (x) => (Number.isFinite(Number(x)) && x !== null && x !== '' ? Number(x) : NaN);
  for (const [k, run] of (runs || []).entries()) {
    const report = run && run.report ? run.report : {};
    const iso = report.isoplanar && typeof report.isoplanar === 'object' ? report.isoplanar : {};
    rows.push({
      key: `run${k}`,
      label: run.label,
      theta: num(iso.theta_deg),
      time: num(iso.estimated_time_s ?? report.estimated_time_s),
      path: num(iso.path_mm ?? report.path_mm),
      rate: num(iso.deposition_rate_mm3_s),
    });
  }
  const first = runs && runs[0] && runs[0].report && runs[0].report.isoplanar;
  const b = first && first.benchmark;
  if (b && (Number.isFinite(b.mean_estimated_time_s) || Number.isFinite(b.mean_path_mm))) {
    rows.push({
      key: 'benchmark',
      label: `mean over ${Number.isFinite(b.directions) ? `${b.directions} ` : ''}directions`,
      theta: NaN,
      time: num(b.mean_estimated_time_s),
      path: num(b.mean_path_mm),
      rate: NaN,
    });
  }
  const base = rows[0];
  for (const r of rows) {
    r.timeDelta = base && base.time > 0 && Number.isFinite(r.time) ? r.time / base.time - 1 : NaN;
    r.pathDelta = base && base.path > 0 && Number.isFinite(r.path) ? r.path / base.path - 1 : NaN;
  }
  return rows;
}
