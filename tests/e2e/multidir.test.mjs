// SPDX-License-Identifier: MIT
// The multi-directional method on the page (issue 7 item 9), in headless Chromium against the
// real worker and wasm module:
//   - the settings panel: the method choice shows the 'Multi-directional' rows (α_max, w, search
//     scheme, beam width, DOF mode, samples; the axis search only for 4 DOF) and hides the planar
//     slicing direction; cartesian3 gets the hint;
//   - an L-bracket STL made here (a column with an arm at its top: 200 mm² of risky underside)
//     loaded through the file input and sliced with multidir on table5: the report's J_G before
//     -> after, the parts table (one row per part), the J_G-per-level chart, the parts drawn in
//     their colours with an arrow each, the order slider, the risky faces before / after (their
//     areas match the report), the program downloads; while the search ran, every search level
//     reached the page (progress.search), drew the live J_G chart and the decompose stage's text;
//   - a planar slice afterwards hides the multidir view and report; no page errors.
// Screenshots go to build/e2e/multidir-*.png.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { OUT_DIR, appPage, tid } from './page-controls.mjs';

const app = appPage('md');
const { page, skip, pageErrors, setSetting, slide, sliceCount, waitSliced, sliceAndWait, downloadProgram } = app;

/**
 * Binary STL of an L-bracket: the L profile (x, z) = column 0..10 x 0..20 with an arm 0..30 x
 * 20..30 on top, extruded along y over 0..10 mm. Closed and outward (flipped by signed volume).
 */
function lBracketStl() {
  const P = [[0, 0], [10, 0], [10, 20], [30, 20], [30, 30], [0, 30], [0, 20]];
  const cap = [[0, 1, 2], [0, 2, 6], [5, 6, 2], [5, 2, 3], [5, 3, 4]];  // counter-clockwise in (x, z)
  const v = (i, y) => [P[i][0], y, P[i][1]];
  const tris = [];
  for (const [a, b, c] of cap) {
    tris.push([v(a, 10), v(b, 10), v(c, 10)]);
    tris.push([v(c, 0), v(b, 0), v(a, 0)]);
  }
  for (let i = 0; i < P.length; i++) {
    const j = (i + 1) % P.length;
    tris.push([v(i, 0), v(j, 0), v(j, 10)], [v(i, 0), v(j, 10), v(i, 10)]);
  }
  let volume = 0;
  for (const [a, b, c] of tris) {
    volume += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6;
  }
  if (volume < 0) for (const t of tris) t.reverse();
  const buf = Buffer.alloc(84 + 50 * tris.length);
  buf.write('L-bracket (omnislice multidir e2e)', 0, 'ascii');
  buf.writeUInt32LE(tris.length, 80);
  tris.forEach((t, k) => {
    const o = 84 + 50 * k;
    t.forEach((p, c) => p.forEach((x, i) => buf.writeFloatLE(x, o + 12 + 12 * c + 4 * i)));
  });
  return { bytes: buf, volume: Math.abs(volume) };
}

test('the method choice shows the multi-directional settings', async (t) => {
  if (skip(t)) return;
  const visible = (id) => page.isVisible(tid(id));
  const rows = ['multidir-alpha', 'multidir-w', 'multidir-scheme', 'multidir-beam-width', 'multidir-dof', 'multidir-samples',
    'multidir-interface-overlap'];
  for (const id of rows) assert.equal(await visible(id), false, `${id} hidden for planar`);
  await setSetting('machine', 'cartesian3');
  await setSetting('setting-method', 'multidir');
  for (const id of rows) assert.equal(await visible(id), true, `${id} shown for multidir`);
  assert.equal(await visible('setting-direction'), false, 'each part has its own direction');
  assert.equal(await visible('multidir-axis-search'), false, 'no axis search for 5 DOF');
  assert.match(await page.textContent(tid('method-hint')), /multidir method turns the part between parts/);
  await setSetting('machine', 'rotary4');
  assert.equal(await visible('multidir-axis-search'), true, 'rotary4: 4 DOF, axis search');
  assert.equal(await page.isHidden(tid('method-hint')), true);
  await setSetting('multidir-scheme', 'greedy');
  assert.equal(await visible('multidir-beam-width'), false, 'no beam width for greedy');
  await setSetting('multidir-scheme', 'beam');
  await setSetting('machine', 'table5');
  const settings = await page.evaluate(() => window.omnislice.settings);
  assert.equal(settings.method, 'multidir');
  assert.equal(settings['multidir.alpha_max_deg'], 45);
});

test('an L-bracket sliced with multidir on table5: parts, arrows, chart, risky faces, program', async (t) => {
  if (skip(t)) return;
  const { bytes, volume } = lBracketStl();
  assert.ok(Math.abs(volume - (10 * 20 * 10 + 30 * 10 * 10)) < 1e-6);
  const file = path.join(app.tmpDir, 'l-bracket.stl');
  fs.writeFileSync(file, bytes);
  await setSetting('setting-layer_height', 0.3);
  const before0 = await sliceCount();
  await page.setInputFiles(tid('file-input'), file);
  await page.waitForFunction(() => document.querySelector('[data-testid="model-name"]').textContent === 'l-bracket.stl'
    && document.body.dataset.state === 'ready', null, { timeout: 120_000 });
  assert.equal(await page.textContent(tid('info-closed')), 'yes');
  await page.click(tid('slice-button'));
  const failed = await waitSliced(before0);
  if (failed) assert.fail(`multidir slice failed: ${failed}`);
  const report = await page.evaluate(() => window.omnislice.report);
  const m = report.multidir;
  assert.ok(m, 'report.multidir');
  assert.ok(Math.abs(m.J_G_before - 200) < 1, `J_G before ${m.J_G_before}`);
  assert.ok(m.J_G_after < 1, `J_G after ${m.J_G_after}`);
  assert.ok(m.part_count >= 2);
  // The panel.
  assert.equal(await page.isVisible(tid('md-report')), true);
  assert.match(await page.textContent(tid('md-jg')), /^200 mm² → 0 mm²/);
  assert.equal(await page.locator(`${tid('md-parts-table')} tbody tr`).count(), m.part_count);
  assert.match(await page.textContent(tid('md-part-0')), /platform/);
  const levels = m.search.J_G_per_level.length;
  assert.ok(levels >= 1);
  assert.equal(await page.getAttribute(tid('md-jg-chart'), 'data-points'), String(levels));
  assert.match(await page.textContent(tid('md-chart-stats')), new RegExp(`^${levels} levels`));
  assert.match(await page.textContent(tid('progress-text')), /parts, J_G 200 → 0 mm²/);
  // While the search ran: every search level reached the page, the live J_G chart was drawn from
  // them (the last drawing: the chosen sequence, the report's values) before the report's chart
  // replaced it, and the stage list's decompose row keeps the last level's text.
  const sp = await page.evaluate(() => window.omnislice.searchProgress);
  assert.deepEqual(sp.levels.filter((s) => s.line === 'chosen').map((s) => s.J_G), m.search.J_G_per_level);
  assert.equal(sp.levels.filter((s) => s.line !== 'chosen' && s.level >= 1).length, m.search.levels);
  assert.ok(sp.liveDraws.length >= 1, 'the live chart was drawn while slicing');
  assert.deepEqual(sp.liveDraws[sp.liveDraws.length - 1], m.search.J_G_per_level);
  assert.equal(await page.getAttribute(tid('md-jg-chart'), 'data-live'), null, 'the report replaced the live chart');
  const levelText = /^search level \d+: J_G = [\d.,]+ mm² \((greedy|constrained|beam|chosen)(, \d+ beams?)?\)$/;
  assert.match(await page.textContent(`${tid('stage-list')} li[data-stage="decompose"] .detail`), levelText);
  assert.match((await page.evaluate(() => window.omnislice.stageDetails)).decompose,
    new RegExp(`^search level ${levels - 1}: J_G = 0 mm² \\(chosen\\)$`));
  // The view: every part and its arrow.
  assert.equal(await page.isVisible(tid('md-bar')), true);
  let v = await page.evaluate(() => window.omnislice.multidir);
  assert.equal(v.parts, m.part_count);
  assert.equal(v.partsShown, m.part_count);
  assert.equal(v.arrowsDrawn, m.part_count);
  assert.equal(v.trianglesDrawn, v.triangles);
  await page.waitForTimeout(300);
  await page.screenshot({ path: path.join(OUT_DIR, 'multidir-parts.png') });
  // The order slider: the platform part alone.
  await slide('md-order-slider', 0);
  v = await page.evaluate(() => window.omnislice.multidir);
  assert.deepEqual([v.partsShown, v.arrowsDrawn], [1, 1]);
  assert.ok(v.trianglesDrawn > 0 && v.trianglesDrawn < v.triangles);
  assert.match(await page.textContent(tid('md-order-text')), new RegExp(`^1 of ${m.part_count}`));
  await slide('md-order-slider', m.part_count - 1);
  // Risky faces before and after: their areas are the report's J_G.
  await setSetting('md-risky', 'before');
  v = await page.evaluate(() => window.omnislice.multidir);
  assert.ok(v.riskyDrawn > 0);
  assert.ok(Math.abs(v.riskyAreaMm2.before - m.J_G_before) < 0.01 * m.J_G_before, `before ${v.riskyAreaMm2.before}`);
  assert.match(await page.textContent(tid('md-risky-text')), /faces, 200 mm²/);
  await page.waitForTimeout(300);
  await page.screenshot({ path: path.join(OUT_DIR, 'multidir-risky-before.png') });
  await setSetting('md-risky', 'after');
  v = await page.evaluate(() => window.omnislice.multidir);
  assert.ok(Math.abs(v.riskyAreaMm2.after - m.J_G_after) < 0.01 * m.J_G_before, `after ${v.riskyAreaMm2.after}`);
  await setSetting('show-arrows', false);
  assert.equal((await page.evaluate(() => window.omnislice.multidir)).arrowsDrawn, 0);
  await setSetting('show-arrows', true);
  await page.locator(tid('md-report')).screenshot({ path: path.join(OUT_DIR, 'multidir-report.png') });
  // The program.
  const { name, text } = await downloadProgram();
  assert.equal(name, 'l-bracket.gcode');
  assert.ok(text.length > 10_000, `${text.length} bytes`);
  assert.ok((text.match(/^; omnislice:layer \d+/gm) || []).length >= report.layers, 'a marker per layer');
});

test('a planar slice afterwards hides the multidir view and report', async (t) => {
  if (skip(t)) return;
  await setSetting('setting-method', 'planar');
  await setSetting('machine', 'cartesian3');
  const failed = await sliceAndWait();
  if (failed) assert.fail(`planar slice failed: ${failed}`);
  assert.equal(await page.isHidden(tid('md-bar')), true);
  assert.equal(await page.isHidden(tid('md-report')), true);
  assert.equal(await page.evaluate(() => window.omnislice.multidir), null);
  // Planar supports by default (auto): the arm's underside is 9 % of the bracket's surface, above
  // auto's 1 %; the page says why, and the struts under the arm are drawn as support lines.
  assert.match(await page.textContent(tid('report-supports')), /^auto: \d+\.\d % of the surface overhangs, above 1 % — .*mm³ printed: \d+ struts/);
  assert.ok((await page.evaluate(() => window.omnislice.featureCounts)).support > 0, 'auto supports in the preview');
  assert.equal(await page.isVisible(tid('support-roof')), true);
  await setSetting('support-mode', 'none');
  assert.equal(await page.isVisible(tid('support-roof')), false, 'no support settings without supports');
  await setSetting('support-mode', 'projected');
  const failedAgain = await sliceAndWait();
  if (failedAgain) assert.fail(`planar slice with supports failed: ${failedAgain}`);
  const sup = (await page.evaluate(() => window.omnislice.report)).support;
  assert.ok(sup && sup.generated && sup.struts > 0 && sup.printed_volume_mm3 > 0, JSON.stringify(sup));
  assert.match(await page.textContent(tid('report-supports')), /mm³ printed: \d+ struts/);
  assert.ok((await page.evaluate(() => window.omnislice.featureCounts)).support > 0, 'support segments in the preview');
  await page.screenshot({ path: path.join(OUT_DIR, 'planar-supports.png') });
});

test('no uncaught page error', (t) => {
  if (skip(t)) return;
  assert.deepEqual(pageErrors(), []);
});
