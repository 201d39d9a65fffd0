// SPDX-License-Identifier: MIT
// Iso-planar paths on the page (issue 5 item 7), in headless Chromium against the real worker and
// wasm module:
//   - the settings panel: method `surface` and fill `isoplanar` show the iso-planar rows (theta
//     forced or searched, directions, chord error, benchmark; the support base for surface);
//   - a synthetic result (report.isoplanar and preview.curves) shown through the page's test hook:
//     the polar plot of v_e(theta) with one path point per sample and theta*, theta* and v_e shown,
//     the side step range, NL curves drawn in alternating colours; a click on the plot chooses the
//     compare direction (folded into [0, 180)) and marks it;
//   - a compare run keeps the first result whether the engine accepts it or not;
//   - the model menu's saddle demo: loaded, the surface method and the UR5 selected (undoable),
//     sliced, the polar plot and NL curves shown;
//   - a real surface slice of a generated saddle (robot6-ur5, nozzle 1, layer 0.75): the polar
//     plot renders with theta* marked, a compare run at another direction adds a second row (with
//     the benchmark means) without replacing the first result, the drawn run can be switched; no
//     page errors; the layer range starts at the surface layer, the layer surfaces start hidden.
// The real slices skip (not in CI) while the engine has no surface method.
// Screenshots go to build/e2e/isoplanar-*.png.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { IN_CI, OUT_DIR, appPage, tid } from './page-controls.mjs';
import { saddleObj } from '../js/fixtures/meshes.js';

const app = appPage('iso');
const { page, skip, pageErrors, setSetting } = app;

test('method surface and fill isoplanar show the iso-planar settings', async (t) => {
  if (skip(t)) return;
  const visible = (id) => page.isVisible(tid(id));
  assert.equal(await page.locator(`${tid('legend-curves')}:visible`).count(), 0, 'no NL curves in the planar demo');
  assert.equal(await visible('iso-report'), false, 'no iso-planar section for a planar slice');
  const iso = ['iso-theta', 'iso-directions', 'iso-chord-error', 'iso-benchmark'];
  for (const id of [...iso, 'surface-base']) assert.equal(await visible(id), false, `${id} hidden for planar`);
  assert.equal(await visible('setting-fill'), true);
  await setSetting('setting-fill', 'isoplanar');
  for (const id of iso) assert.equal(await visible(id), true, `${id} shown for fill = isoplanar`);
  assert.equal(await visible('surface-base'), false);
  await setSetting('setting-fill', 'auto');
  await setSetting('setting-method', 'surface');
  assert.match(await page.textContent(tid('method-hint')), /surface method .*choose table5, head4, head5 or a robot/, 'cartesian3 cannot follow the normal');
  for (const id of [...iso, 'surface-base']) assert.equal(await visible(id), true, `${id} shown for surface`);
  await setSetting('iso-theta', 40);
  assert.equal((await page.evaluate(() => window.omnislice.settings))['isoplanar.theta_deg'], 40);
  await page.click(tid('settings-undo'));
  assert.equal((await page.evaluate(() => window.omnislice.settings))['isoplanar.theta_deg'], -1);
  await setSetting('setting-method', 'planar');
});

// A synthetic iso-planar result: a zig-zag of C NL curves (drive planes 1 mm apart along y) on a
// saddle patch, a base layer below; v_e(theta) = 0.5 + 0.1 cos(2 (theta - 158°)) every 2 degrees.
function syntheticIsoResult({ C, starDeg }) {
  const ve = (d) => 0.5 + 0.1 * Math.cos((2 * (d - starDeg) * Math.PI) / 180);
  const curve = Array.from({ length: 90 }, (_, i) => [2 * i, ve(2 * i)]);
  const positions = [];
  const features = [];
  const layers = [];
  const curves = [];
  const machine = [];
  const push = (a, b, f, l, c) => {
    positions.push(...a, ...b);
    features.push(f);
    layers.push(l);
    curves.push(c);
    machine.push(...b, 0, 0, 0);
  };
  // Base: one planar layer (not on a curve).
  for (let k = 0; k < 20; k++) push([-10, -10 + k, 0], [10, -10 + k, 0], 4, 0, 0);
  let prev = null;
  for (let c = 1; c <= C; c++) {
    const y = -10 + (20 * (c - 1)) / (C - 1);
    const xs = Array.from({ length: 21 }, (_, i) => -10 + i);
    if (c % 2 === 0) xs.reverse();
    const pts = xs.map((x) => [x, y, 2 + (x * x - y * y) / 100]);
    if (prev) push(prev, pts[0], 0, 1, 0);  // the join between curves
    for (let i = 1; i < pts.length; i++) push(pts[i - 1], pts[i], 1, 1, c);
    prev = pts[pts.length - 1];
  }
  const report = {
    method: 'surface', layers: 2, path_mm: 900, extrusion_mm: 40, estimated_time_s: 120, timings_ms: { total: 800 },
    program_format: 'csv', machine: 'robot6-ur5', machine_kind: 'robot6',
    isoplanar: {
      theta_deg: starDeg, deposition_rate_mm3_s: ve(starDeg), curve, path_mm: 420, estimated_time_s: 60,
      benchmark: { mean_estimated_time_s: 68, mean_path_mm: 430, directions: 90 }, forced: false, planes: C,
      side_step_mm: { min: 0.83, max: 1.27 }, mean_width_mm: 1.05, mean_feed_mm_s: 14.2, unreachable: 0, samples: 441,
      timings_ms: { search: 120, paths: 80 },
    },
  };
  return {
    programBytes: new TextEncoder().encode('; synthetic\n'),
    programExtension: 'csv',
    report,
    preview: {
      positions: new Float32Array(positions), features: new Uint8Array(features), layers: new Uint32Array(layers),
      machine: new Float32Array(machine), curves: new Uint32Array(curves),
    },
  };
}

test('a synthetic iso-planar result: polar plot with theta*, side steps, alternating NL curves, click to choose', async (t) => {
  if (skip(t)) return;
  const C = 21;
  await page.evaluate(async ([fnText, args]) => {
    // eslint-disable-next-line no-new-func
    const make = new Function(`return (${fnText})`)();
    await window.omnislice._showResultForTest(make(args));
  }, [syntheticIsoResult.toString(), { C, starDeg: 158 }]);
  assert.equal(await page.isVisible(tid('iso-report')), true);
  const svg = page.locator(tid('iso-polar'));
  assert.equal(await svg.getAttribute('data-samples'), '90');
  assert.equal(await svg.getAttribute('data-theta-star'), '158');
  // One closed path: a point per sample at theta and at theta + 180.
  const d = await page.locator(`${tid('iso-polar')} path.curve`).getAttribute('d');
  assert.equal(d.split(/[ML]/).length - 1, 180);
  assert.match(d, /Z$/);
  assert.equal(await page.locator(tid('iso-star-mark')).count(), 1, 'theta* marked');
  assert.equal(await page.locator(`${tid('iso-polar')} circle.star-dot`).count(), 2, 'theta* dots at both ends');
  assert.equal(await page.textContent(tid('iso-theta-star')), '158°');
  assert.equal(await page.textContent(tid('iso-ve-star')), '0.6 mm³/s');
  assert.equal(await page.textContent(tid('iso-side-step')), '0.83–1.27 mm');
  assert.equal(await page.inputValue(tid('iso-compare-theta')), '68', 'the compare direction proposed: theta* + 90 folded');
  assert.equal(await svg.getAttribute('data-compare-theta'), '68', 'and marked');
  assert.equal(await page.textContent(tid('iso-planes')), String(C));
  // NL curves drawn in the curve colours, every one of them.
  const iso = await page.evaluate(() => window.omnislice.isoplanar);
  assert.equal(iso.curveCount, C);
  assert.equal(await page.inputValue(tid('layer-min-slider')), '1', 'the layer range starts at the NL curves\' layer');
  assert.equal(await page.locator(`${tid('legend-curves')}:visible`).count(), 2, 'the legend names the two curve colours');
  assert.equal(iso.compare, null);
  assert.deepEqual(iso.rows.map((r) => r.key), ['run0', 'benchmark']);
  assert.equal(await page.locator(`${tid('iso-compare-table')} tbody tr`).count(), 2, 'first run and benchmark means');
  assert.equal(await page.textContent(`${tid('iso-compare-benchmark')} td`), 'mean over 90 directions');
  // A click up-left of the centre at 135 degrees (SVG y is down) chooses 135 and marks it.
  const box = await svg.boundingBox();
  const r = 0.3 * box.width;
  await page.mouse.click(box.x + box.width / 2 - r * Math.SQRT1_2, box.y + box.height / 2 - r * Math.SQRT1_2);
  assert.equal(await page.inputValue(tid('iso-compare-theta')), '135');
  assert.equal(await svg.getAttribute('data-compare-theta'), '135');
  assert.equal(await page.locator(tid('iso-compare-mark')).count(), 1);
  assert.equal(await page.locator(tid('iso-candidate-mark')).count(), 0, 'no candidate before a comparison ran');
  // Below the centre: the same plane as above (folded into [0, 180)).
  await page.mouse.click(box.x + box.width / 2, box.y + box.height / 2 + r);
  assert.equal(await page.inputValue(tid('iso-compare-theta')), '90');
  await page.waitForTimeout(300);
  await page.locator(tid('iso-report')).screenshot({ path: path.join(OUT_DIR, 'isoplanar-synthetic-report.png') });
  await page.screenshot({ path: path.join(OUT_DIR, 'isoplanar-synthetic.png') });
  assert.deepEqual(pageErrors(), []);
});

test('a compare run keeps the first result, whether the engine accepts it or not', async (t) => {
  if (skip(t)) return;
  // The synthetic result of the previous test is shown; the engine re-slices the loaded demo.
  await page.fill(tid('iso-compare-theta'), '30');
  await page.click(tid('iso-compare-button'));
  await page.waitForFunction(() => (document.body.dataset.state === 'done' && Number(document.body.dataset.compareCount) >= 1)
    || document.body.dataset.state === 'error', null, { timeout: 180_000 });
  const state = await page.evaluate(() => document.body.dataset.state);
  const view = await page.evaluate(() => window.omnislice.isoplanar);
  assert.equal(view.rows[0].theta, 158, 'the first run is still the synthetic one');
  assert.equal(await page.evaluate(() => window.omnislice.report.isoplanar.theta_deg), 158);
  assert.equal(await page.getAttribute(tid('iso-polar'), 'data-theta-star'), '158');
  if (state === 'error') {
    t.diagnostic(`compare refused: ${await page.textContent(tid('error-message'))}`);
    assert.equal(view.compare, null);
    assert.equal(await page.locator(`${tid('iso-compare-table')} tbody tr.run`).count(), 1);
  } else {
    assert.equal(view.compare.theta, 30);
    assert.equal(await page.locator(`${tid('iso-compare-table')} tbody tr.run`).count(), 2);
  }
  assert.deepEqual(pageErrors(), []);
});

test('the model menu loads and slices the saddle demo with the surface method', async (t) => {
  if (skip(t)) return;
  const before = await page.evaluate(() => Number(document.body.dataset.sliceCount || 0));
  await page.selectOption(tid('demo-model'), 'saddle');
  // The state may still be 'error' from the refused comparison: wait for the new model's slice.
  await page.waitForFunction((n) => (document.body.dataset.state === 'done' && Number(document.body.dataset.sliceCount) > n)
    || (document.body.dataset.state === 'error' && !document.querySelector('[data-testid="error-message"]').textContent.includes('isoplanar.theta_deg')),
  before, { timeout: 300_000 });
  const settings = await page.evaluate(() => window.omnislice.settings);
  assert.equal(settings.method, 'surface', 'the demo selects the surface method');
  assert.equal(settings.machine, 'robot6-ur5', 'and a machine that can follow the surface normal');
  assert.equal(await page.isHidden(tid('method-hint')), true);
  assert.equal(await page.textContent(tid('model-name')), 'demo-saddle.obj');
  assert.equal(await page.textContent(tid('info-faces')), '3,200');
  assert.equal(await page.textContent(tid('info-closed')), 'no');
  if (await page.evaluate(() => document.body.dataset.state) === 'error') {
    const message = await page.textContent(tid('error-message'));
    if (!IN_CI && /invalid_option: .*(method|surface|fill)/.test(message)) {
      // Put the settings back for the next test.
      await page.click(tid('settings-undo'));
      await page.click(tid('settings-undo'));
      return t.skip(`the engine does not slice with method=surface yet: ${message}`);
    }
    assert.fail(`demo slice failed: ${message}`);
  }
  const report = await page.evaluate(() => window.omnislice.report);
  assert.ok(report.isoplanar && report.isoplanar.theta_deg >= 0, 'report.isoplanar');
  t.diagnostic(`saddle demo: theta* ${report.isoplanar.theta_deg}, v_e ${report.isoplanar.deposition_rate_mm3_s}, curves ${report.isoplanar.curves}`);
  assert.equal(await page.isVisible(tid('iso-report')), true);
  assert.equal(Number(await page.getAttribute(tid('iso-polar'), 'data-theta-star')), report.isoplanar.theta_deg);
  assert.ok((await page.evaluate(() => window.omnislice.isoplanar)).curveCount > 1);
  assert.deepEqual(pageErrors(), []);
  // Undo brings the machine and the method back like any other edit.
  await page.click(tid('settings-undo'));
  await page.click(tid('settings-undo'));
  const back = await page.evaluate(() => window.omnislice.settings);
  assert.equal(back.method, 'planar');
  assert.equal(back.machine, 'cartesian3');
});

test('a real surface slice of a saddle: polar plot, compare run side by side, switch the drawn run', async (t) => {
  if (skip(t)) return;
  const file = path.join(app.tmpDir, 'saddle.obj');
  fs.writeFileSync(file, saddleObj(100, 30, 30));
  await setSetting('setting-method', 'surface');
  await setSetting('machine', 'robot6-ur5');
  await setSetting('setting-nozzle', 1);
  await setSetting('setting-layer_height', 0.75);
  await page.setInputFiles(tid('file-input'), file);
  await page.waitForFunction(() => (document.body.dataset.state === 'ready'
    && document.querySelector('[data-testid="model-name"]').textContent === 'saddle.obj')
    || document.body.dataset.state === 'error', null, { timeout: 60_000 });
  assert.equal(await page.evaluate(() => document.body.dataset.state), 'ready', await page.textContent(tid('error-message')));
  const before = await page.evaluate(() => Number(document.body.dataset.sliceCount || 0));
  const started = Date.now();
  await page.click(tid('slice-button'));
  await page.waitForFunction((n) => (document.body.dataset.state === 'done' && Number(document.body.dataset.sliceCount) > n)
    || document.body.dataset.state === 'error', before, { timeout: 300_000 });
  if (await page.evaluate(() => document.body.dataset.state) === 'error') {
    const message = await page.textContent(tid('error-message'));
    // Until the engine has the surface method (issue 5's pipeline, branch iso), it refuses it.
    if (!IN_CI && /invalid_option: .*(method|surface|fill)/.test(message)) {
      return t.skip(`the engine does not slice with method=surface yet: ${message}`);
    }
    assert.fail(`surface slice failed: ${message}`);
  }
  t.diagnostic(`surface slice of the saddle: ${Date.now() - started} ms wall`);
  const first = await page.evaluate(() => window.omnislice.report);
  const iso = first.isoplanar;
  assert.ok(iso && Array.isArray(iso.curve) && iso.curve.length > 1, 'report.isoplanar.curve');
  t.diagnostic(`theta* ${iso.theta_deg}, v_e ${iso.deposition_rate_mm3_s}, time ${iso.estimated_time_s} s, path ${iso.path_mm} mm, benchmark ${JSON.stringify(iso.benchmark)}`);
  const svg = page.locator(tid('iso-polar'));
  assert.equal(await svg.getAttribute('data-samples'), String(iso.curve.length));
  assert.equal(Number(await svg.getAttribute('data-theta-star')), iso.theta_deg);
  assert.equal(await page.locator(tid('iso-star-mark')).count(), 1);
  assert.match(await page.textContent(tid('iso-ve-star')), /mm³\/s$/);
  const view = await page.evaluate(() => window.omnislice.isoplanar);
  assert.ok(view.curveCount > 1, `NL curves drawn in alternating colours: ${view.curveCount}`);
  assert.equal(await page.isChecked(tid('show-surfaces')), false, 'the surface layer starts hidden so the NL curves show');
  // The surface layer is printed last, on its base: the layer range starts there.
  const lastLayer = Number(await page.getAttribute(tid('layer-min-slider'), 'max'));
  assert.ok(lastLayer > 0, 'base layers below the surface layer');
  assert.equal(Number(await page.inputValue(tid('layer-min-slider'))), lastLayer, 'the layer range starts at the surface layer');
  // Compare with the direction 90 degrees away from theta*.
  const other = (iso.theta_deg + 90) % 180;
  await page.fill(tid('iso-compare-theta'), String(other));
  await page.click(tid('iso-compare-button'));
  await page.waitForFunction(() => (document.body.dataset.state === 'done' && Number(document.body.dataset.compareCount) >= 1)
    || document.body.dataset.state === 'error', null, { timeout: 300_000 });
  assert.equal(await page.evaluate(() => document.body.dataset.state), 'done', await page.textContent(tid('error-message')));
  const after = await page.evaluate(() => window.omnislice.isoplanar);
  assert.equal(after.compare.theta, other);
  assert.equal(after.compare.report.isoplanar.theta_deg, other, 'the compared run used the forced direction');
  assert.equal(after.compare.report.isoplanar.forced, true);
  const runs = await page.locator(`${tid('iso-compare-table')} tbody tr.run`).count();
  assert.equal(runs, 2, 'two runs side by side');
  // The first result stays: report, theta* mark.
  assert.deepEqual(await page.evaluate(() => window.omnislice.report.isoplanar.theta_deg), iso.theta_deg);
  assert.equal(Number(await svg.getAttribute('data-theta-star')), iso.theta_deg);
  assert.equal(Number(await svg.getAttribute('data-compare-theta')), other);
  // A new direction typed after the comparison is drawn as the next candidate; the compared one stays.
  const next = (other + 45) % 180;
  await page.fill(tid('iso-compare-theta'), String(next));
  assert.equal(Number(await svg.getAttribute('data-candidate-theta')), next);
  assert.equal(Number(await svg.getAttribute('data-compare-theta')), other);
  assert.equal(await page.locator(tid('iso-candidate-mark')).count(), 1);
  const rows = after.rows;
  assert.equal(rows[0].time, iso.estimated_time_s);
  assert.equal(rows[1].time, after.compare.report.isoplanar.estimated_time_s);
  if (iso.benchmark) assert.equal(rows[rows.length - 1].key, 'benchmark');
  // The drawn run can be switched and back.
  await page.selectOption(tid('iso-show-run'), '1');
  await page.waitForFunction(() => window.omnislice.isoplanar.shownRun === 1 && document.body.dataset.state === 'done');
  await page.waitForTimeout(300);
  await page.screenshot({ path: path.join(OUT_DIR, 'isoplanar-compare.png') });
  await page.selectOption(tid('iso-show-run'), '0');
  await page.waitForFunction(() => window.omnislice.isoplanar.shownRun === 0);
  // A tall viewport so the whole section fits (the panel scrolls).
  await page.setViewportSize({ width: 1280, height: 1600 });
  await page.locator(tid('iso-report')).screenshot({ path: path.join(OUT_DIR, 'isoplanar-report.png') });
  await page.setViewportSize({ width: 1280, height: 900 });
  assert.deepEqual(pageErrors(), []);
});
