// SPDX-License-Identifier: MIT
// End-to-end tests of the machine side of the page in headless Chromium (playwright-core), against
// the real worker and wasm module served by scripts/serve.mjs on a free port:
//   - the machine panel: the four built-in machines, the G-code flavour shown for G-code machines
//     and the robot program format only for the robot;
//   - robot6-ur5 on the demo: the report names the machine and shows the motion figures, the
//     download is a .csv joint program, then a .script URScript program after choosing urscript;
//   - the machine animation: the machine-step slider moved over the program and play/pause; at
//     every step shown, the tip error measured in the drawn scene (platform matrix applied to the
//     move's part-frame end point vs the drawn nozzle tip) stays under 0.01 mm;
//   - the downloaded robot CSV replayed through its declared machine (the program-file input)
//     animates with the tip on the point too; a broken program shows parse_error;
//   - table5 with the Klipper flavour writes B and C axis words;
//   - a broken machine profile file shows parse_error with the core's message; a valid rotary4
//     profile file is used for the next slice (A axis words) until "use built-in".
// Screenshots go to build/e2e/machine-*.png.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { OUT_DIR, appPage, tid } from './page-controls.mjs';

const TIP_TOLERANCE_MM = 0.01;

const app = appPage('machine', { height: 800, required: true });
const { page, pageErrors, sliceAndWait, downloadProgram: download } = app;

/** Click Slice; the report once the slice is done (a failed slice fails the test). */
async function slice() {
  const error = await sliceAndWait(180_000);
  if (error !== null) assert.fail(`slice failed: ${error}`);
  return page.evaluate(() => window.omnislice.report);
}

/** Move the step slider to s; returns the animation state the page reports. */
async function stepTo(s) {
  await page.locator(tid('machine-step')).fill(String(s));
  return page.evaluate(() => ({
    step: Number(document.querySelector('[data-testid="machine-step"]').dataset.step),
    tipError: Number(document.querySelector('[data-testid="machine-step"]').dataset.tipError),
    machine: window.omnislice.machine,
  }));
}

/** Open the machine view and sweep the slider over the program; returns the worst tip error. */
async function sweepMachine(label) {
  await page.check(tid('machine-toggle'));
  await page.waitForSelector(`${tid('machine-bar')}:not([hidden])`);
  const { steps } = await page.evaluate(() => window.omnislice.machine);
  const segments = await page.evaluate(() => window.omnislice.previewSegments);
  assert.equal(steps, segments, `${label}: one animation step per preview segment`);
  let worst = 0;
  const picks = [0, 1, Math.floor(steps / 7), Math.floor(steps / 3), Math.floor(steps / 2), Math.floor((2 * steps) / 3), steps - 2, steps - 1];
  for (let k = 0; k < 25; k++) picks.push(Math.floor(((k + 0.5) * steps) / 25));
  for (const s of picks) {
    const r = await stepTo(s);
    assert.equal(r.step, s, `${label}: slider at ${s}`);
    assert.equal(r.machine.step, s);
    assert.ok(Number.isFinite(r.tipError), `${label}: tip error at ${s} is a number`);
    worst = Math.max(worst, r.tipError);
  }
  assert.ok(worst < TIP_TOLERANCE_MM, `${label}: worst tip error ${worst} mm over ${picks.length} steps`);
  return { steps, worst };
}

test('the machine panel lists the built-in machines; flavour for G-code, format for the robot', async () => {
  const options = await page.$$eval(`${tid('machine')} option`, (os) => os.map((o) => o.value));
  assert.deepEqual(options, ['cartesian3', 'rotary4', 'table5', 'head4', 'head5', 'robot6-ur5', 'robot6-ur5-rated', 'robot6-irb1200', 'robot6-kr6']);
  assert.equal(await page.isVisible(tid('gcode-flavor')), true);
  assert.equal(await page.isVisible(tid('robot-format')), false);
  await page.selectOption(tid('machine'), 'robot6-ur5');
  assert.equal(await page.isVisible(tid('gcode-flavor')), false);
  assert.equal(await page.isVisible(tid('robot-format')), true);
  assert.equal(await page.evaluate(() => window.omnislice.settings.machine), 'robot6-ur5');
  // The select lists exactly the core's built-ins; "save JSON" downloads the selected profile.
  const names = await page.evaluate(async () => (await (await import('/workers/engine.js')).createSlicer()
    .then(async (s) => { const list = await s.machines(); s.dispose(); return list.map((x) => x.name); })));
  assert.deepEqual(options, names);
  const [d] = await Promise.all([page.waitForEvent('download'), page.click(tid('machine-save'))]);
  assert.equal(d.suggestedFilename(), 'robot6-ur5.json');
  const file = path.join(app.tmpDir, 'saved-robot6-ur5.json');
  await d.saveAs(file);
  const saved = JSON.parse(fs.readFileSync(file, 'utf8'));
  assert.equal(saved.kind, 'robot6');
  assert.equal(saved.dh.length, 6);
});

test('robot6-ur5: report and motion figures, .csv then .script downloads, animation on the nozzle', async (t) => {
  await page.selectOption(tid('machine'), 'robot6-ur5');
  await page.selectOption(tid('robot-format'), 'csv');
  const report = await slice();
  assert.equal(report.machine_kind, 'robot6');
  assert.match(await page.textContent(tid('report-machine')), /robot6/);
  assert.equal(await page.isVisible(tid('report-motion')), true);
  assert.match(await page.textContent(tid('motion-samples')), /^[\d,]+$/);
  assert.match(await page.textContent(tid('motion-max_joint_step')), /^[\d.]+ rad \([\d.]+°\)$/);
  // The greedy comparison is shown in brackets when the planner computed it (null otherwise).
  const greedy = report.motion.greedy_pose_cost;
  assert.match(await page.textContent(tid('motion-pose_cost')),
    Number.isFinite(greedy) ? /^[\d.,]+ rad \([\d.,]+ rad\)$/ : /^[\d.,]+ rad$/);
  assert.ok(report.motion.samples > 0, JSON.stringify(report.motion));
  assert.equal(await page.textContent(tid('motion-samples')), report.motion.samples.toLocaleString('en'));
  assert.equal(await page.textContent(tid('motion-subdivisions')), report.motion.subdivisions.toLocaleString('en'));
  assert.equal(await page.evaluate(() => window.omnislice.programExtension), 'csv');
  const csv = await download();
  assert.equal(csv.name, 'demo-overhang.csv');
  assert.match(csv.text, /^# /m, 'CSV header comments');
  assert.match(csv.text, /^-?[\d.]+(,-?[\d.eE+-]+){7},(print|travel|support)$/m, 'joint rows');

  const { steps, worst } = await sweepMachine('robot6-ur5');
  t.diagnostic(`robot6-ur5: ${steps} steps, worst tip error ${worst.toExponential(2)} mm`);
  await page.uncheck(tid('machine-toggle'));

  // Replay the downloaded CSV through its declared machine: the animation shows the file.
  const csvFile = path.join(app.tmpDir, 'replay-me.csv');
  fs.writeFileSync(csvFile, csv.text);
  await page.setInputFiles(tid('program-file'), csvFile);
  await page.waitForFunction(() => window.omnislice.machine && window.omnislice.machine.replay === 'replay-me.csv');
  assert.equal(await page.isChecked(tid('machine-toggle')), true);
  assert.match(await page.textContent(tid('machine-step-text')), /^replay-me\.csv: move /);
  const replayed = await page.evaluate(() => window.omnislice.machine);
  assert.equal(replayed.kind, 'robot6');
  assert.ok(replayed.steps >= steps * 0.9, `replayed ${replayed.steps} pieces, sliced ${steps} segments`);
  let worstReplay = 0;
  for (const s of [0, Math.floor(replayed.steps / 4), Math.floor(replayed.steps / 2), replayed.steps - 1]) {
    worstReplay = Math.max(worstReplay, (await stepTo(s)).tipError);
  }
  assert.ok(worstReplay < TIP_TOLERANCE_MM, `replayed CSV: tip error ${worstReplay}`);
  // A broken program shows the reader's error code.
  const badFile = path.join(app.tmpDir, 'bad.csv');
  fs.writeFileSync(badFile, csv.text.split('\n').slice(0, 40).join('\n') + '\n1,2,oops\n');
  await page.setInputFiles(tid('program-file'), badFile);
  await page.waitForSelector(`${tid('error-message')}:not([hidden])`);
  assert.match(await page.textContent(tid('error-message')), /^parse_error: bad\.csv: /);
  await page.uncheck(tid('machine-toggle'));
  await page.check(tid('machine-toggle'));
  await page.waitForTimeout(400);
  await page.screenshot({ path: path.join(OUT_DIR, 'machine-robot6.png') });

  // Play, then pause: the step advances and the tip stays on the point.
  const start = await stepTo(0);
  await page.click(tid('machine-play'));
  assert.equal(await page.getAttribute(tid('machine-play'), 'aria-pressed'), 'true');
  await page.waitForFunction(() => window.omnislice.machine.step > 3, null, { timeout: 20_000 });
  await page.click(tid('machine-play'));
  assert.equal(await page.getAttribute(tid('machine-play'), 'aria-pressed'), 'false');
  const paused = await page.evaluate(() => window.omnislice.machine);
  assert.ok(paused.step > start.step, `played from ${start.step} to ${paused.step}`);
  assert.ok(paused.tipError < TIP_TOLERANCE_MM, `tip error after playing ${paused.tipError}`);
  await page.waitForTimeout(200);
  assert.equal((await page.evaluate(() => window.omnislice.machine)).step, paused.step, 'paused');

  // URScript: a new slice (the machine view follows it) and a .script download.
  await page.selectOption(tid('robot-format'), 'urscript');
  await slice();
  assert.equal(await page.evaluate(() => window.omnislice.programExtension), 'script');
  const script = await download();
  assert.equal(script.name, 'demo-overhang.script');
  assert.match(script.text, /^def \w+\(\):/m);
  assert.match(script.text, /^end$/m);
  const after = await stepTo(Math.floor(steps / 2));
  assert.ok(after.tipError < TIP_TOLERANCE_MM, `after re-slicing: ${after.tipError}`);
  await page.uncheck(tid('machine-toggle'));
  assert.equal(await page.isVisible(tid('machine-bar')), false);
});

test('table5 with the Klipper flavour: B and C axis words; the animation keeps the tip on the point', async (t) => {
  await page.selectOption(tid('machine'), 'table5');
  await page.selectOption(tid('gcode-flavor'), 'klipper');
  const report = await slice();
  assert.equal(report.machine_kind, 'table5');
  const g = await download();
  assert.equal(g.name, 'demo-overhang.gcode');
  assert.match(g.text, /^G[01] .* B-?[\d.]+/m);
  assert.match(g.text, /^G[01] .* C-?[\d.]+/m);
  const { steps, worst } = await sweepMachine('table5');
  t.diagnostic(`table5: ${steps} steps, worst tip error ${worst.toExponential(2)} mm`);
  await page.waitForTimeout(400);
  await page.screenshot({ path: path.join(OUT_DIR, 'machine-table5.png') });
  await page.uncheck(tid('machine-toggle'));
  await page.selectOption(tid('gcode-flavor'), 'marlin');
});

test('head5 with firmware axis letters and thumbnails: U and V words, PNG blocks; the animated head keeps the tip on the point', async (t) => {
  await page.selectOption(tid('machine'), 'head5');
  await page.selectOption(tid('setting-method'), 'multidir');  // parts printed with the head tilted
  await page.selectOption(tid('gcode-flavor'), 'reprap');
  await page.fill(tid('setting-axis_letters'), 'B=U,C=V');
  await page.dispatchEvent(tid('setting-axis_letters'), 'change');
  await page.fill(tid('setting-thumbnails'), '32x32');
  await page.dispatchEvent(tid('setting-thumbnails'), 'change');
  const report = await slice();
  assert.equal(report.machine_kind, 'head5');
  assert.deepEqual(report.machine_profile.axis_letters, { B: 'U', C: 'V' });
  const g = await download();
  assert.match(g.text, /^G[01] .* U-?[\d.]+ V-?[\d.]+/m);
  assert.doesNotMatch(g.text, /^G[01] [^;]* [BC]-?[\d.]+/m);
  assert.match(g.text, /^; thumbnail begin 32x32 \d+$/m);
  assert.match(g.text, /^G[01] .* U-?[1-9][\d.]*/m, 'the head tilts (U is B)');
  const { steps, worst } = await sweepMachine('head5');
  t.diagnostic(`head5: ${steps} steps, worst tip error ${worst.toExponential(2)} mm`);
  await page.waitForTimeout(400);
  await page.screenshot({ path: path.join(OUT_DIR, 'machine-head5.png') });
  await page.uncheck(tid('machine-toggle'));
  for (const key of ['axis_letters', 'thumbnails']) {
    await page.fill(tid(`setting-${key}`), '');
    await page.dispatchEvent(tid(`setting-${key}`), 'change');
  }
  await page.selectOption(tid('gcode-flavor'), 'marlin');
  await page.selectOption(tid('setting-method'), 'planar');
  await page.selectOption(tid('machine'), 'table5');  // as the table5 test left it
});

test('machine profile files: a broken one shows parse_error; a rotary4 one is used until "use built-in"', async () => {
  const broken = path.join(app.tmpDir, 'broken-machine.json');
  fs.writeFileSync(broken, '{"kind": "rotary4", "pivot": [0, 0');
  await page.setInputFiles(tid('machine-file'), broken);
  await page.waitForSelector(`${tid('error-message')}:not([hidden])`);
  assert.equal(await page.getAttribute(tid('error-message'), 'data-code'), 'parse_error');
  assert.match(await page.textContent(tid('error-message')), /^parse_error: broken-machine\.json: machine JSON: \S/);

  const limits = path.join(app.tmpDir, 'inverted-limits.json');
  fs.writeFileSync(limits, JSON.stringify({ kind: 'rotary4', axis_limits: { A: [60, -60] } }));
  await page.setInputFiles(tid('machine-file'), limits);
  await page.waitForFunction(() => /inverted-limits/.test(document.querySelector('[data-testid="error-message"]').textContent));
  assert.equal(await page.getAttribute(tid('error-message'), 'data-code'), 'parse_error');

  const good = path.join(app.tmpDir, 'my-rotary.json');
  fs.writeFileSync(good, JSON.stringify({
    kind: 'rotary4', pivot: [0, 0, 0], axis_limits: { X: [-150, 150], Y: [-150, 150], Z: [-50, 250], A: [-90, 90] },
    nozzle: { diameter: 0.4, cone_half_angle_deg: 40, cone_length: 25 },
  }, null, 2));
  await page.setInputFiles(tid('machine-file'), good);
  await page.waitForFunction(() => /my-rotary\.json/.test(document.querySelector('[data-testid="machine-profile"]').textContent));
  assert.equal(await page.isDisabled(tid('machine')), true, 'the built-in select is off while a file profile is used');
  assert.equal(await page.isVisible(tid('gcode-flavor')), true);
  assert.ok(JSON.parse(await page.evaluate(() => window.omnislice.settings.machine_json)).kind === 'rotary4');
  const report = await slice();
  assert.equal(report.machine_kind, 'rotary4');
  const g = await download();
  assert.equal(g.name, 'demo-overhang.gcode');
  assert.match(g.text, /^G[01] .* A-?[\d.]+/m, 'A axis words');
  const { worst } = await sweepMachine('rotary4 (profile file)');
  assert.ok(worst < TIP_TOLERANCE_MM);
  await page.uncheck(tid('machine-toggle'));

  await page.click(tid('machine-builtin'));
  assert.equal(await page.isDisabled(tid('machine')), false);
  assert.equal(await page.evaluate(() => window.omnislice.settings.machine_json), undefined);
  assert.match(await page.textContent(tid('machine-profile')), /built-in profile table5/);
});

test('the page raised no uncaught error', () => {
  assert.deepEqual(pageErrors(), []);
});
