// SPDX-License-Identifier: MIT
// What the page's iso-planar view reads from the wasm module (Node), on a generated saddle with
// the surface method on robot6-ur5: report.isoplanar's fields (the polar plot's curve, theta*,
// the side steps, the benchmark means) and preview.curves (one 1-based NL curve index per
// segment, numbered in print order, the report's curve count), checked through the page's own
// helpers (web/methods/isoplanar-data.js); a forced direction gives a forced report at that direction.
// Skipped (not under CI) while the engine has no surface method.
import { before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { CI, loadShipped, wasmUnavailable } from './wasm-support.mjs';
import { saddleObj } from './fixtures/meshes.js';
import { comparisonRows, curveStats, hasCurves, polarPlotGeometry, readCurve } from '../../web/methods/isoplanar-data.js';

const why = wasmUnavailable();
if (why && CI) throw new Error(`wasm tests cannot run under CI: ${why}`);

const SETTINGS = { method: 'surface', machine: 'robot6-ur5', nozzle_diameter: 1, layer_height: 0.75 };

describe('iso-planar results of the wasm module for the page (Node)', { skip: why ? `skipped: ${why}` : false }, () => {
  let m;
  let bytes;
  let first = null;
  let unavailable = null;
  before(async () => {
    ({ module: m } = await loadShipped());
    bytes = new TextEncoder().encode(saddleObj(100, 30, 30));
    try {
      first = m.slice(bytes, 'saddle.obj', SETTINGS);
    } catch (err) {
      if (!CI && err.code === 'invalid_option' && /surface|method/.test(err.message)) unavailable = err.message;
      else throw err;
    }
  });

  test('report.isoplanar and preview.curves of a surface slice', (t) => {
    if (unavailable) return t.skip(`the engine has no surface method yet: ${unavailable}`);
    const iso = first.report.isoplanar;
    assert.ok(iso && typeof iso === 'object', 'report.isoplanar');
    // The polar plot's input: [[theta, v_e]] with theta in [0, 180), theta* among the directions.
    const curve = readCurve(iso.curve);
    assert.ok(curve.length >= 2, `curve samples: ${curve.length}`);
    assert.ok(iso.theta_deg >= 0 && iso.theta_deg < 180, `theta* ${iso.theta_deg}`);
    assert.equal(iso.forced, false);
    assert.ok(iso.deposition_rate_mm3_s > 0, `v_e(theta*) ${iso.deposition_rate_mm3_s}`);
    const g = polarPlotGeometry(iso.curve, { thetaStar: iso.theta_deg, valueStar: iso.deposition_rate_mm3_s });
    assert.ok(g.star.value >= g.vMax * (1 - 1e-9), `v_e(theta*) ${g.star.value} is the maximum of the curve ${g.vMax}`);
    for (const k of ['path_mm', 'estimated_time_s', 'mean_width_mm']) assert.ok(iso[k] > 0, `${k}: ${iso[k]}`);
    assert.ok(iso.side_step_mm && iso.side_step_mm.min > 0 && iso.side_step_mm.max >= iso.side_step_mm.min,
      `side steps ${JSON.stringify(iso.side_step_mm)}`);
    assert.ok(iso.benchmark && iso.benchmark.mean_estimated_time_s > 0 && iso.benchmark.mean_path_mm > 0,
      `benchmark ${JSON.stringify(iso.benchmark)}`);
    // preview.curves: one index per segment, numbered in print order, as many as the report says.
    const p = first.preview;
    assert.ok(hasCurves(p), `curves ${p.curves && p.curves.length} for ${p.features.length} segments`);
    const stats = curveStats(p.curves);
    assert.ok(stats.count >= 2, `NL curves drawn: ${stats.count}`);
    assert.equal(stats.ordered, true, 'curve indices never decrease along the print order');
    if (Number.isFinite(iso.curves)) assert.equal(stats.count, iso.curves, 'report.isoplanar.curves');
    for (let s = 0; s < p.features.length; s++) if (p.features[s] === 0) assert.equal(p.curves[s], 0, `travel segment ${s} is on no curve`);
    t.diagnostic(`theta* ${iso.theta_deg}, v_e ${iso.deposition_rate_mm3_s}, ${stats.count} curves over ${stats.onCurves} of ${stats.segments} segments, side step ${JSON.stringify(iso.side_step_mm)}`);
  });

  test('a forced direction: the compare run the page makes', (t) => {
    if (unavailable) return t.skip(`the engine has no surface method yet: ${unavailable}`);
    const theta = (first.report.isoplanar.theta_deg + 90) % 180;
    const forced = m.slice(bytes, 'saddle.obj', { ...SETTINGS, 'isoplanar.theta_deg': theta });
    const iso = forced.report.isoplanar;
    assert.equal(iso.forced, true);
    assert.ok(Math.abs(iso.theta_deg - theta) < 1e-9, `forced theta ${iso.theta_deg}`);
    const rows = comparisonRows([{ label: 'first', report: first.report }, { label: 'forced', report: forced.report }]);
    assert.equal(rows[1].theta, iso.theta_deg);
    assert.ok(rows[1].rate <= rows[0].rate * (1 + 1e-9), `v_e at theta* ${rows[0].rate} >= at ${theta}: ${rows[1].rate}`);
    t.diagnostic(`time ${rows[0].time} s at theta* vs ${rows[1].time} s at ${theta}; path ${rows[0].path} vs ${rows[1].path} mm`);
  });
});
