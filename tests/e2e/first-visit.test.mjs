// SPDX-License-Identifier: MIT
// The first visit (issue 28 item 3), in headless Chromium against the real worker and wasm module:
// the page at / opens the post with three arms (scripts/make-demo-arms.mjs) on table5 with
// method = auto and slices it. What a new user sees must show what multi-axis printing buys:
// every method table5 takes ran and was checked, planar layers needed supports under the arms,
// and the program written is a verified multi-axis one with next to no support, in the side-by-
// side table with the chosen row marked. Slicing it again, no main-thread task over 50 ms while
// the candidates run and their results are shown (issue 28's target; long-tasks.mjs).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import path from 'node:path';
import { OUT_DIR, appPage, tid } from './page-controls.mjs';
import { longTaskCheck } from './long-tasks.mjs';

const app = appPage('first-visit', { path: '/' });
const { page, skip, pageErrors, downloadProgram } = app;
const { sliceWithLongTaskCheck } = longTaskCheck(app);

test('the first visit slices the arms demo with auto on table5: a sound multi-axis program over planar with supports', async (t) => {
  if (skip(t)) return;
  assert.equal(await page.textContent(tid('model-name')), 'demo-arms.obj');
  const settings = await page.evaluate(() => window.omnislice.settings);
  assert.equal(settings.machine, 'table5');
  assert.equal(settings.method, 'auto');
  const report = await page.evaluate(() => window.omnislice.report);
  const candidates = Object.fromEntries(report.auto.candidates.map((c) => [c.method, c]));
  assert.deepEqual(Object.keys(candidates).sort(), ['geodesic', 'multidir', 'planar', 'voxel']);
  for (const c of report.auto.candidates) {
    t.diagnostic(`${c.method}: ${c.status}, sound ${c.verify && c.verify.sound}, supported ${c.verify && c.verify.supported}, `
      + `support ${c.support_volume_mm3} mm3, ${(c.estimated_time_s / 3600).toFixed(2)} h, ${c.timings_ms.total.toFixed(0)} ms`);
  }
  // Planar layers need supports under the arms (70° from vertical).
  assert.equal(candidates.planar.status, 'ok');
  assert.ok(candidates.planar.support_volume_mm3 > 100, `planar support ${candidates.planar.support_volume_mm3} mm3`);
  // The chosen program: a multi-axis method, verified sound, with under a tenth of planar's support.
  const chosen = candidates[report.auto.chosen];
  assert.notEqual(report.auto.chosen, 'planar');
  assert.equal(report.method, report.auto.chosen);
  assert.equal(chosen.verify.sound, true);
  assert.equal(chosen.verify.collisions, 0);
  assert.equal(chosen.verify.left_out_mm, 0);
  assert.ok(chosen.support_volume_mm3 < 0.1 * candidates.planar.support_volume_mm3,
    `${report.auto.chosen} support ${chosen.support_volume_mm3} mm3 against planar ${candidates.planar.support_volume_mm3}`);
  assert.equal(report.verify.sound, true);
  // The comparison as the user sees it: a row per candidate, the chosen one marked, the reason.
  assert.equal(await page.isVisible(tid('auto-report')), true);
  const rows = await page.$$eval(`${tid('auto-candidates')} tr`, (trs) => trs.map((tr) => ({
    method: tr.cells[0].textContent, state: tr.dataset.state,
  })));
  assert.deepEqual(rows.map((r) => r.method).sort(), ['geodesic', 'multidir', 'planar', 'voxel']);
  assert.deepEqual(rows.filter((r) => r.state === 'chosen').map((r) => r.method), [report.auto.chosen]);
  assert.equal(await page.textContent(tid('auto-reason')), report.auto.reason);
  assert.match(report.auto.reason, /planar \(\d+ mm\^3 of support\)/);
  // The program downloads as the chosen method's, for table5.
  const { name, text } = await downloadProgram();
  assert.equal(name, 'demo-arms.gcode');
  assert.ok(text.includes(`; omnislice:setting method = ${report.auto.chosen}`));
  assert.ok(text.includes('; omnislice:setting machine = table5'));
  await page.screenshot({ path: path.join(OUT_DIR, 'first-visit.png') });
  assert.deepEqual(pageErrors(), []);
});

test('the four candidates run and show without a main-thread task over 50 ms', async (t) => {
  if (skip(t)) return;
  const workers = await page.evaluate(() => window.omnislice.workers);
  t.diagnostic(`${workers} worker(s)`);
  const rec = await sliceWithLongTaskCheck(t, 'auto on the arms demo');
  assert.ok(rec.texts.some((x) => /^done in [\d.]+ s: auto chose \w+ of 4/.test(x)), JSON.stringify(rec.texts.slice(-3)));
  assert.deepEqual(pageErrors(), []);
});
