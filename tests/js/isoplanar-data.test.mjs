// SPDX-License-Identifier: MIT
// The iso-planar view's data helpers (web/methods/isoplanar-data.js) on synthetic reports: the polar plot
// of v_e(theta) closed by the theta + 180 symmetry, the theta* marker on the curve, clicks folded
// into [0, 180), periodic interpolation, NL curve colours alternating, the figures and the
// comparison table of two runs with the benchmark means.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import {
  CURVE_COLORS, comparisonRows, curveColor, curveStats, curveValueAt, foldTheta, hasCurves, isoplanarSummaryRows,
  polarPlotGeometry, readCurve, ringValues, sideStepText, thetaFromPlotPoint,
} from '../../web/methods/isoplanar-data.js';
import { percentText } from '../../web/format.js';

// A synthetic curve with a known maximum: v_e(theta) = 0.5 + 0.1 cos(2 (theta - 158°)), sampled
// every 4 degrees (45 samples), in shuffled order.
const STAR = 158;
const ve = (t) => 0.5 + 0.1 * Math.cos(2 * (t - STAR) * Math.PI / 180);
const SAMPLES = Array.from({ length: 45 }, (_, i) => [4 * i, ve(4 * i)]);
const SHUFFLED = SAMPLES.map((p, i) => [p, (i * 17) % 45]).sort((a, b) => a[1] - b[1]).map(([p]) => p);

const close = (a, b, tol, what) => assert.ok(Math.abs(a - b) <= tol, `${what}: ${a} vs ${b}`);

test('foldTheta folds any angle into [0, 180)', () => {
  for (const [t, f] of [[0, 0], [179.5, 179.5], [180, 0], [181, 1], [-1, 179], [-180, 0], [540, 0], [359, 179]]) {
    close(foldTheta(t), f, 1e-12, `fold ${t}`);
  }
});

test('readCurve sorts and rejects malformed samples', () => {
  const sorted = readCurve(SHUFFLED);
  assert.equal(sorted.length, 45);
  for (let i = 1; i < sorted.length; i++) assert.ok(sorted[i][0] > sorted[i - 1][0]);
  assert.throws(() => readCurve({}), /not an array/);
  assert.throws(() => readCurve([[180, 1]]), /outside \[0, 180\)/);
  assert.throws(() => readCurve([[-1, 1]]), /outside/);
  assert.throws(() => readCurve([[10, -0.1]]), /non-negative/);
  assert.throws(() => readCurve([[10, NaN]]), /non-negative/);
  assert.throws(() => readCurve([[10]]), /pair/);
  assert.throws(() => polarPlotGeometry([]), /no samples/);
});

test('curveValueAt interpolates linearly, periodic over 180 degrees', () => {
  const sorted = readCurve(SAMPLES);
  for (const [t, v] of SAMPLES) close(curveValueAt(sorted, t), v, 1e-12, `at sample ${t}`);
  close(curveValueAt(sorted, 10), (ve(8) + ve(12)) / 2, 1e-12, 'midway');
  // Between the last sample (176) and the first one again (180 = 0).
  close(curveValueAt(sorted, 178), (ve(176) + ve(0)) / 2, 1e-12, 'wrap');
  close(curveValueAt(sorted, 178 + 180), curveValueAt(sorted, 178), 1e-12, 'theta + 180');
  close(curveValueAt(sorted, -2), curveValueAt(sorted, 178), 1e-12, 'negative');
  assert.ok(Number.isNaN(curveValueAt([], 3)));
  assert.equal(curveValueAt([[5, 0.7]], 100), 0.7);
});

test('ringValues are round steps up to the maximum', () => {
  assert.deepEqual(ringValues(0.6), [0.2, 0.4, 0.6]);
  assert.deepEqual(ringValues(0.599), [0.2, 0.4]);
  assert.deepEqual(ringValues(7.3), [2, 4, 6]);
  assert.deepEqual(ringValues(0), []);
  assert.deepEqual(ringValues(NaN), []);
});

test('the polar plot is closed by symmetry and theta* sits on the curve at its maximum', () => {
  const size = 220;
  const g = polarPlotGeometry(SHUFFLED, { size, thetaStar: STAR, valueStar: ve(STAR) });
  assert.equal(g.samples, 45);
  assert.equal(g.points.length, 90, 'each sample at theta and at theta + 180');
  assert.ok(g.path.startsWith('M') && g.path.endsWith('Z'), 'a closed path');
  assert.equal(g.path.split(/[ML]/).length - 1, 90, 'one path command per point');
  // Every point lies at radius v_e * scale from the centre, in its direction (y up).
  const sorted = readCurve(SAMPLES);
  for (let i = 0; i < 90; i++) {
    const [t, v] = sorted[i % 45];
    const theta = t + (i >= 45 ? 180 : 0);
    const [x, y] = g.points[i];
    close(Math.hypot(x - g.cx, y - g.cy), v * g.scale, 1e-9, `radius of point ${i}`);
    const angle = (Math.atan2(g.cy - y, x - g.cx) * 180) / Math.PI;
    close(((angle - theta) % 360 + 540) % 360 - 180, 0, 1e-9, `direction of point ${i}`);
  }
  // Symmetry: the point at theta + 180 mirrors the one at theta through the centre.
  for (let i = 0; i < 45; i++) {
    close(g.points[i][0] + g.points[i + 45][0], 2 * g.cx, 1e-9, 'mirror x');
    close(g.points[i][1] + g.points[i + 45][1], 2 * g.cy, 1e-9, 'mirror y');
  }
  // Inside the box, the maximum within the outermost ring.
  for (const [x, y] of g.points) assert.ok(x >= 0 && x <= size && y >= 0 && y <= size);
  assert.ok(0.6 * g.scale <= g.radius + 1e-9, 'the marked value within the plot');
  close(g.vMax, ve(156), 1e-12, 'vMax: the sampled maximum');
  close(g.vMin, Math.min(...SAMPLES.map((p) => p[1])), 1e-12, 'vMin');
  assert.deepEqual(g.best, { theta: 156, value: ve(156) }, 'the sampled maximum (4° grid)');
  // The marker: both dots at v_e(theta*) along theta* and theta* + 180, the line through the centre.
  assert.equal(g.star.theta, STAR);
  close(g.star.value, 0.6, 1e-12, 'marked value');
  const [d0, d1] = g.star.dots;
  close(Math.hypot(d0[0] - g.cx, d0[1] - g.cy), 0.6 * g.scale, 1e-9, 'dot radius');
  close(d0[0] + d1[0], 2 * g.cx, 1e-9, 'dots mirrored');
  close(thetaFromPlotPoint(d0[0], d0[1], g.cx, g.cy, 0.001), STAR, 1e-3, 'dot direction');
  const [a, b] = g.star.line;
  close((a[0] + b[0]) / 2, g.cx, 1e-9, 'line through the centre');
  close((a[1] + b[1]) / 2, g.cy, 1e-9, 'line through the centre');
  close(Math.hypot(a[0] - g.cx, a[1] - g.cy), g.rings[g.rings.length - 1].r, 1e-9, 'line to the outer ring');
  // Rings at round values, radius proportional.
  assert.deepEqual(g.rings.map((r) => r.value), [0.2, 0.4, 0.6]);
  for (const r of g.rings) close(r.r, r.value * g.scale, 1e-9, 'ring radius');
});

test('without theta* the marker is the sampled argmax; extra marks interpolate', () => {
  const g = polarPlotGeometry(SAMPLES, { extra: [30, 'x', 200] });
  assert.equal(g.star.theta, 156);
  close(g.star.value, ve(156), 1e-12, 'argmax value');
  assert.equal(g.marks.length, 2, 'non-numbers are left out');
  assert.equal(g.marks[0].theta, 30);
  close(g.marks[0].value, ve(28) + (ve(32) - ve(28)) / 2, 1e-12, 'interpolated at 30');
  assert.equal(g.marks[1].theta, 20, '200 folds to 20');
  // theta* = -1 (searched but not reported) falls back to the argmax too.
  assert.equal(polarPlotGeometry(SAMPLES, { thetaStar: -1 }).star.theta, 156);
});

test('thetaFromPlotPoint folds clicks into [0, 180)', () => {
  const c = 100;
  assert.equal(thetaFromPlotPoint(150, 100, c, c), 0, '+x');
  assert.equal(thetaFromPlotPoint(100, 50, c, c), 90, 'up is +y');
  assert.equal(thetaFromPlotPoint(50, 100, c, c), 0, '-x is the same plane as +x');
  assert.equal(thetaFromPlotPoint(100, 150, c, c), 90, 'down folds to 90');
  assert.equal(thetaFromPlotPoint(150, 150, c, c), 135, '-45 folds to 135');
  assert.equal(thetaFromPlotPoint(100 + 50 * Math.cos(Math.PI * 0.99), 100 - 50 * Math.sin(Math.PI * 0.99), c, c), 178, '178.2 rounds to 178');
  assert.equal(thetaFromPlotPoint(100 + 50 * Math.cos(Math.PI * 0.999), 100 - 50 * Math.sin(Math.PI * 0.999), c, c), 0, '179.8 rounds to 180 = 0');
  assert.equal(thetaFromPlotPoint(100, 100, c, c), null, 'the centre has no direction');
  assert.equal(thetaFromPlotPoint(150, 150, c, c, 5), 135);
});

test('NL curves alternate between two colours; curve statistics', () => {
  assert.equal(curveColor(0), null);
  assert.deepEqual(curveColor(1), CURVE_COLORS[0]);
  assert.deepEqual(curveColor(2), CURVE_COLORS[1]);
  assert.deepEqual(curveColor(7), CURVE_COLORS[0]);
  assert.notDeepEqual(CURVE_COLORS[0], CURVE_COLORS[1]);
  // Adjacent curves (c, c + 1) never share a colour.
  for (let c = 1; c < 50; c++) assert.notDeepEqual(curveColor(c), curveColor(c + 1));
  const curves = new Uint32Array([0, 1, 1, 0, 2, 2, 2, 0, 3, 0]);
  assert.deepEqual(curveStats(curves), { segments: 10, onCurves: 6, count: 3, ordered: true });
  assert.equal(curveStats(new Uint32Array([2, 1])).ordered, false);
  assert.deepEqual(curveStats(null), { segments: 0, onCurves: 0, count: 0, ordered: true });
  assert.equal(hasCurves({ features: new Uint8Array(3), curves: new Uint32Array(3) }), true);
  assert.equal(hasCurves({ features: new Uint8Array(3), curves: new Uint32Array(0) }), false);
  assert.equal(hasCurves({ features: new Uint8Array(3), curves: new Uint32Array(2) }), false, 'lengths disagree');
  assert.equal(hasCurves({ features: new Uint8Array(3) }), false);
});

const REPORT = {
  estimated_time_s: 1300,
  path_mm: 7300,
  isoplanar: {
    theta_deg: 158, deposition_rate_mm3_s: 0.599, curve: SAMPLES, path_mm: 7034.7, estimated_time_s: 1100,
    benchmark: { mean_estimated_time_s: 1233, mean_path_mm: 7130, directions: 180 },
    forced: false, planes: 41, side_step_mm: { min: 0.72, max: 1.31 }, mean_width_mm: 1.02,
    mean_feed_mm_s: 18.5, unreachable: 0, samples: 20000, timings_ms: { search: 412.4, paths: 1234.5 },
  },
};

test('summary rows of report.isoplanar', () => {
  const rows = Object.fromEntries(isoplanarSummaryRows(REPORT.isoplanar).map(([k, label, text]) => [k, [label, text]]));
  assert.deepEqual(rows.theta, ['θ* (searched)', '158°']);
  assert.equal(rows.deposition_rate[1], '0.599 mm³/s');
  assert.equal(rows.side_step[1], '0.72–1.31 mm');
  assert.equal(rows.planes[1], '41');
  assert.equal(rows.curves, undefined, 'no NL curve count in this report');
  assert.deepEqual(isoplanarSummaryRows({ curves: 57, paths: 3 }).filter(([k]) => k === 'curves' || k === 'paths').map(([, , x]) => x), ['57', '3']);
  assert.equal(rows.directions[1], '180');
  assert.equal(rows.samples[1], '20,000');
  assert.equal(rows.time[1], '18 min 20 s');
  assert.equal(rows.time_search[1], '412 ms');
  assert.equal(rows.time_paths[1], '1.23 s');
  const forced = Object.fromEntries(isoplanarSummaryRows({ ...REPORT.isoplanar, forced: true, theta_deg: 30 }).map(([k, l, t]) => [k, [l, t]]));
  assert.deepEqual(forced.theta, ['θ (forced)', '30°']);
  // Absent figures show a dash, nothing throws.
  for (const [, , text] of isoplanarSummaryRows(null)) assert.equal(text, '—');
  assert.equal(sideStepText({ side_step_mm: { min: 1 } }), '—');
});

test('comparison rows: two runs and the benchmark means, deltas against the first run', () => {
  const forced = {
    estimated_time_s: 1500, path_mm: 7500,
    isoplanar: { ...REPORT.isoplanar, theta_deg: 60, forced: true, deposition_rate_mm3_s: 0.41, path_mm: 7200, estimated_time_s: 1300 },
  };
  const rows = comparisonRows([{ label: 'θ* = 158°', report: REPORT }, { label: 'θ = 60°', report: forced }]);
  assert.deepEqual(rows.map((r) => r.key), ['run0', 'run1', 'benchmark']);
  assert.deepEqual(rows.map((r) => r.theta).slice(0, 2), [158, 60]);
  assert.deepEqual(rows.map((r) => r.time), [1100, 1300, 1233], 'the iso-planar paths\' times');
  assert.deepEqual(rows.map((r) => r.path), [7034.7, 7200, 7130]);
  assert.equal(rows[0].rate, 0.599);
  assert.equal(rows[1].rate, 0.41);
  assert.ok(Number.isNaN(rows[2].rate));
  assert.equal(rows[2].label, 'mean over 180 directions');
  assert.equal(rows[0].timeDelta, 0);
  close(rows[1].timeDelta, 1300 / 1100 - 1, 1e-12, 'time delta');
  close(rows[2].pathDelta, 7130 / 7034.7 - 1, 1e-12, 'path delta');
  // Without report.isoplanar's own figures the program's are used; no benchmark row without means.
  const plain = comparisonRows([{ label: 'a', report: { estimated_time_s: 10, path_mm: 20 } }]);
  assert.equal(plain.length, 1);
  assert.equal(plain[0].time, 10);
  assert.equal(plain[0].path, 20);
  assert.ok(Number.isNaN(plain[0].rate));
  assert.deepEqual(comparisonRows([]), []);
});

test('percentText', () => {
  assert.equal(percentText(-0.108), '−10.8 %');
  assert.equal(percentText(0.0321), '+3.2 %');
  assert.equal(percentText(0.0001), '0 %');
  assert.equal(percentText(NaN), '');
});
