// SPDX-License-Identifier: MIT
// method = auto on the page (issue 28 item 1), in headless Chromium against the real worker and
// wasm module, on the demo model on rotary4 (planar and multidir take it): the candidates show
// side by side in the order they ran, the chosen one marked and the same as the report's method,
// whose own sections show as when chosen by hand; the done line says what auto chose; the
// program downloads; "use" on the other candidate slices again with its method.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { appPage, tid } from './page-controls.mjs';

const { page, skip, pageErrors, setSetting, sliceAndWait, downloadProgram } = appPage('auto');

test('auto runs planar and multidir on rotary4 and shows them side by side, the best chosen', async (t) => {
  if (skip(t)) return;
  await setSetting('machine', 'rotary4');
  await setSetting('setting-method', 'auto');
  assert.equal(await sliceAndWait(), null);
  const report = await page.evaluate(() => window.omnislice.report);
  assert.deepEqual(report.auto.candidates.map((c) => c.method), ['planar', 'multidir']);
  assert.equal(report.method, report.auto.chosen);
  assert.equal(await page.isVisible(tid('auto-report')), true);
  const rows = await page.$$eval(`${tid('auto-candidates')} tr`, (trs) => trs.map((tr) => ({
    method: tr.cells[0].textContent, state: tr.dataset.state, check: tr.cells[1].textContent,
  })));
  assert.deepEqual(rows.map((r) => r.method), ['planar', 'multidir']);
  assert.deepEqual(rows.filter((r) => r.state === 'chosen').map((r) => r.method), [report.auto.chosen]);
  assert.equal(await page.textContent(tid('auto-chosen')), report.auto.chosen);
  assert.equal(await page.textContent(tid('auto-reason')), report.auto.reason);
  assert.match(await page.textContent(tid('progress-text')), new RegExp(`^done in [\\d.]+ s: auto chose ${report.auto.chosen} of 2`));
  if (report.auto.chosen === 'multidir') assert.equal(await page.isVisible(tid('md-report')), true);
  // In a pool of workers (this machine has 2 cores) each candidate's stages are listed as its own.
  const workers = await page.evaluate(() => window.omnislice.workers);
  t.diagnostic(`auto ran in ${workers} worker(s)`);
  if (workers > 1) {
    const stages = await page.$$eval(`${tid('stage-list')} li`, (lis) => lis.map((li) => li.dataset.stage));
    for (const m of ['planar', 'multidir']) assert.ok(stages.some((st) => st.startsWith(`${m} · `)), stages.join(', '));
    // Each candidate's program as a small picture in its row.
    for (const m of ['planar', 'multidir']) {
      const lines = await page.getAttribute(tid(`auto-thumb-${m}`), 'data-lines');
      assert.ok(Number(lines) > 100, `${m}: ${lines} lines drawn`);
    }
  }
  const { name, text } = await downloadProgram();
  assert.match(name, /\.gcode$/);
  assert.ok(text.includes(`; omnislice:setting method = ${report.auto.chosen}`));
  // Another candidate is one click away: its own program, the method setting undoable.
  const other = report.auto.candidates.find((c) => c.method !== report.auto.chosen && c.status === 'ok');
  if (other) {
    t.diagnostic(`use ${other.method} (sound: ${other.verify && other.verify.sound})`);
    await page.click(tid(`auto-use-${other.method}`));
    await page.waitForFunction((m) => window.omnislice.report && window.omnislice.report.method === m && !window.omnislice.report.auto, other.method, { timeout: 300_000 });
    assert.equal(await page.evaluate(() => window.omnislice.settings.method), other.method);
    assert.equal(await page.isHidden(tid('auto-report')), true);
    if (workers > 1 && other.verify && other.verify.sound) {
      // Held by the pool's result: shown without slicing again (the stage list is still auto's).
      const stages = await page.$$eval(`${tid('stage-list')} li`, (lis) => lis.map((li) => li.dataset.stage));
      assert.ok(stages.includes('auto'), stages.join(', '));
    }
    const { text: otherText } = await downloadProgram();
    assert.ok(otherText.includes(`; omnislice:setting method = ${other.method}`));
  }
  assert.deepEqual(pageErrors(), []);
});
