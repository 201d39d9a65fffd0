// SPDX-License-Identifier: MIT
// The voxel method on the page (issue 4 item 10), in headless Chromium against the real worker
// and wasm module:
//   - the settings panel: the method choice shows the voxel rows (and hides the planar-only ones);
//   - a synthetic voxel result (the result shape of slicer.slice(): report.voxel and the preview's
//     surface / voxel / axis buffers), shown through the page's test hook: the voxel figures, the
//     thickness histogram (one bar per bin, the mean and spread shown), the layer surfaces (the
//     surface slider changes the drawn triangle count by exactly the layers' triangles, and the
//     tool-path slider follows), missed and support cells, axis glyphs, the program download;
//   - a real voxel slice of the bundled demo at a coarse voxel width: progress names the voxel
//     stages, the report's voxel figures and histogram show, the surfaces and the missed count
//     render, the slider filters them, and the program downloads with a layer marker per layer.
// Screenshots go to build/e2e/voxel-*.png.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import path from 'node:path';
import { IN_CI, OUT_DIR, appPage, tid } from './page-controls.mjs';
import { pageFields } from '../js/page-settings.mjs';

const { page, skip, pageErrors, setSetting, slide, downloadProgram } = appPage('voxel', { height: 800 });

/** Set a range input's value and fire `input` (as a drag does). */
test('the method choice shows the voxel settings and hides the planar-only ones', async (t) => {
  if (skip(t)) return;
  const visible = (id) => page.isVisible(tid(id));
  assert.equal(await visible('voxel-strategy'), false, 'voxel rows hidden for planar');
  assert.equal(await visible('setting-infill'), true);
  await setSetting('setting-method', 'voxel');
  for (const id of ['voxel-width', 'voxel-strategy', 'voxel-shadow', 'voxel-peel-step', 'voxel-epsilon', 'voxel-layer-field',
    'voxel-smooth', 'voxel-layer-mm', 'voxel-iso-step', 'voxel-max-tilt', 'voxel-supports', 'voxel-platform-radius', 'voxel-max-voxels']) {
    assert.equal(await visible(id), true, `${id} shown for voxel`);
  }
  for (const id of ['setting-infill_pattern', 'setting-layer_height']) assert.equal(await visible(id), false, `${id} hidden for voxel`);
  for (const id of ['setting-infill', 'setting-walls']) assert.equal(await visible(id), true, `${id} shown for voxel (sparse curved layers)`);
  await setSetting('voxel-strategy', 'gcfa');
  assert.equal(await visible('voxel-shadow'), false, 'plain GCFA has no shadow prevention');
  await setSetting('voxel-strategy', 'pg-sp-gcfa');
  await setSetting('voxel-width', 0.9);
  const settings = await page.evaluate(() => window.omnislice.settings);
  assert.equal(settings.method, 'voxel');
  assert.equal(settings['voxel.width_mm'], 0.9);
  // Undo restores through the history like every other setting.
  await page.click(tid('settings-undo'));
  assert.equal(await page.evaluate(() => window.omnislice.settings['voxel.width_mm']), 0);
  await setSetting('setting-method', 'planar');
  assert.equal(await visible('voxel-strategy'), false);
  assert.equal(await visible('setting-infill'), true);
});

// A synthetic voxel result built in the page: L curved layers (a paraboloid patch grid per layer),
// a spiral-ish tool-path per layer with tilted axes, some missed and support cells.
function syntheticResult({ L, n, missed, support }) {
  const surfacePositions = [];
  const surfaceTriangles = [];
  const surfaceLayers = [];
  for (let l = 0; l < L; l++) {
    const base = surfacePositions.length / 3;
    for (let i = 0; i <= n; i++) {
      for (let j = 0; j <= n; j++) {
        const x = -10 + (20 * i) / n;
        const y = -10 + (20 * j) / n;
        surfacePositions.push(x, y, 1 + 0.4 * l + 0.02 * (x * x + y * y) * (1 - l / L));
      }
    }
    // Layer l has (l % 3 + 1) * n rows of quads, so layers differ in triangle count.
    const rows = Math.min(n, (l % 3 + 1) * Math.ceil(n / 3));
    for (let i = 0; i < rows; i++) {
      for (let j = 0; j < n; j++) {
        const a = base + i * (n + 1) + j;
        surfaceTriangles.push(a, a + n + 1, a + 1, a + 1, a + n + 1, a + n + 2);
        surfaceLayers.push(l, l);
      }
    }
  }
  const positions = [];
  const features = [];
  const layers = [];
  const axes = [];
  const machine = [];
  for (let l = 0; l < L; l++) {
    let prev = null;
    for (let k = 0; k <= 120; k++) {
      const a = (k / 120) * 6 * Math.PI;
      const r = 9 * (1 - k / 130);
      const p = [r * Math.cos(a), r * Math.sin(a), 1 + 0.4 * l + 0.02 * r * r * (1 - l / L)];
      if (prev) {
        positions.push(...prev, ...p);
        features.push(k === 1 ? 0 : 4);
        layers.push(l);
        const ax = [-0.04 * p[0], -0.04 * p[1], 1];
        const norm = Math.hypot(...ax);
        axes.push(...ax.map((x) => x / norm));
        machine.push(...p, 0, 0, 0);
      }
      prev = p;
    }
  }
  const missedVoxels = [];
  for (let i = 0; i < missed; i++) missedVoxels.push(-8 + i, 8, 2 + 0.4 * i);
  const supportVoxels = [];
  for (let i = 0; i < support; i++) supportVoxels.push(-8 + (i % 5) * 0.4, 8, 0.2 + 0.4 * Math.floor(i / 5));
  const counts = [0, 2, 9, 30, 61, 40, 12, 3, 0, 1];
  const report = {
    method: 'voxel', layers: L, path_mm: 1000, extrusion_mm: 40, estimated_time_s: 300, timings_ms: { total: 5000 },
    program_format: 'gcode', machine: 'table5', machine_kind: 'table5',
    voxel: {
      voxels: 12345, solid_voxels: 11000, support_voxels: support, missed_voxels: missed, field_layers: 3 * L, layers: L, regions: L + 2,
      strategy: 'pg-sp-gcfa', shadow_scheme: 'recursive', voxel_width_mm: 0.4, iso_step: 1,
      thickness: { samples: counts.reduce((a, b) => a + b, 0), mean_mm: 0.33, std_mm: 0.04, max_deviation_mm: 0.16,
        histogram: { min_mm: -0.125, bin_mm: 0.025, counts } },
      timings_ms: { voxelize: 50, peeling: 800, shadow: 300, growth: 1200, extraction: 400, toolpaths: 900 },
      shadow_checks: 4321, hull_builds: 3 * L, orientation_fallbacks: 0,
    },
  };
  const program = `; synthetic voxel program\n${Array.from({ length: L }, (_, l) => `; omnislice:layer ${l}\nG1 X0 Y0 Z${(1 + 0.4 * l).toFixed(2)} E1\n`).join('')}`;
  return {
    programBytes: new TextEncoder().encode(program),
    programExtension: 'gcode',
    report,
    preview: {
      positions: new Float32Array(positions), features: new Uint8Array(features), layers: new Uint32Array(layers),
      machine: new Float32Array(machine), axes: new Float32Array(axes),
      surfacePositions: new Float32Array(surfacePositions), surfaceTriangles: new Uint32Array(surfaceTriangles),
      surfaceLayers: new Uint32Array(surfaceLayers), missedVoxels: new Float32Array(missedVoxels),
      supportVoxels: new Float32Array(supportVoxels), voxelWidth: 0.4,
    },
    // Expected triangle counts per layer (for the test).
    perLayer: Array.from({ length: L }, (_, l) => surfaceLayers.filter((x) => x === l).length),
    program,
  };
}

test('a synthetic voxel result: figures, histogram, layer surfaces with the slider, cells, glyphs, download', async (t) => {
  if (skip(t)) return;
  const L = 14;
  const out = await page.evaluate(async ([fnText, args]) => {
    // eslint-disable-next-line no-new-func
    const make = new Function(`return (${fnText})`)();
    const r = make(args);
    await window.omnislice._showResultForTest(r);
    return { perLayer: r.perLayer, program: r.program };
  }, [syntheticResult.toString(), { L, n: 12, missed: 5, support: 20 }]);
  const total = out.perLayer.reduce((a, b) => a + b, 0);
  assert.equal(await page.evaluate(() => document.body.dataset.state), 'done');
  // Figures and histogram.
  assert.equal(await page.isVisible(tid('voxel-report')), true);
  assert.equal(await page.textContent(tid('voxel-voxels')), '12,345');
  assert.equal(await page.textContent(tid('voxel-missed_voxels')), '5');
  assert.equal(await page.textContent(tid('voxel-time_growth')), '1.20 s');
  const hist = await page.evaluate(() => {
    const svg = document.querySelector('[data-testid="thickness-histogram"]');
    const bars = [...svg.querySelectorAll('rect.bar')].map((r) => ({ h: Number(r.getAttribute('height')), empty: r.classList.contains('empty') }));
    const x = (sel) => [...svg.querySelectorAll(sel)].map((l) => Number(l.getAttribute('x1')));
    return { bars, total: svg.dataset.total, mean: x('line.mean'), std: x('line.std'), ticks: [...svg.querySelectorAll('text.tick')].map((t) => t.textContent) };
  });
  assert.equal(hist.bars.length, 10);
  assert.equal(hist.total, '158');
  assert.deepEqual(hist.bars.map((b) => b.empty), [true, false, false, false, false, false, false, false, true, false]);
  assert.ok(hist.bars[4].h > hist.bars[3].h && hist.bars[3].h > hist.bars[2].h, 'bars follow the counts');
  // Plot x from 6 to 254 spans -0.125..0.125 mm: deviation 0 at 130, ± 0.04 mm at 130 ± 39.68.
  assert.equal(hist.mean.length, 1, 'deviation 0 (the mean) is marked');
  assert.ok(Math.abs(hist.mean[0] - 130) < 1e-6, `mean line at ${hist.mean[0]}`);
  assert.deepEqual(hist.std.map((x) => Math.round((x - 130) * 100) / 100), [-39.68, 39.68]);
  assert.deepEqual(hist.ticks, ['-0.1', '-0.05', '0', '0.05', '0.1']);
  assert.match(await page.textContent(tid('thickness-stats')), /mean 0\.33 mm, std 0\.04 mm, max deviation 0\.16 mm \(158 samples\)/);
  assert.match(await page.textContent(tid('progress-text')), /done in [\d.]+ s: 42 field layers → 14 layers, 16 regions, 5 missed/);
  // Layer surfaces and the sliders.
  assert.equal(await page.isVisible(tid('voxel-bar')), true);
  assert.equal(await page.textContent(tid('missed-count')), '5');
  assert.equal(await page.textContent(tid('support-count')), '20');
  let v = await page.evaluate(() => window.omnislice.voxel);
  assert.equal(v.surfaceLayers, L);
  assert.equal(v.drawnTriangles, total, 'all layers drawn at first');
  assert.equal(v.missedDrawn, 5);
  assert.equal(v.supportDrawn, 0);
  const segmentsAll = await page.evaluate(() => window.omnislice.drawnSegments[0]);
  for (const hi of [0, 4, 9]) {
    await slide('layer-surface-slider', hi);
    v = await page.evaluate(() => window.omnislice.voxel);
    const expected = out.perLayer.slice(0, hi + 1).reduce((a, b) => a + b, 0);
    assert.equal(v.drawnTriangles, expected, `layers 0..${hi}`);
    assert.equal(v.currentTriangles, out.perLayer[hi]);
    assert.equal(await page.inputValue(tid('layer-slider')), String(hi), 'the tool-path slider follows');
    assert.match(await page.textContent(tid('surface-layer-text')), new RegExp(`^${hi + 1} of ${L} `));
  }
  const segments = await page.evaluate(() => window.omnislice.drawnSegments[0]);
  assert.ok(segments < segmentsAll && segments > 0, `tool-paths filtered too: ${segments} of ${segmentsAll}`);
  await slide('layer-slider', 6);
  assert.equal(await page.inputValue(tid('layer-surface-slider')), '6', 'the surface slider follows the tool-path slider');
  // Toggles.
  await page.check(tid('axis-glyphs-toggle'));
  await page.check(tid('show-support'));
  v = await page.evaluate(() => window.omnislice.voxel);
  assert.ok(v.glyphsDrawn > 0 && v.glyphsDrawn < v.glyphs, `glyphs of layers 0..6: ${v.glyphsDrawn} of ${v.glyphs}`);
  assert.equal(v.supportDrawn, 20);
  await page.waitForTimeout(400);
  await page.screenshot({ path: path.join(OUT_DIR, 'voxel-synthetic.png') });
  await page.locator(tid('voxel-report')).screenshot({ path: path.join(OUT_DIR, 'voxel-synthetic-report.png') });
  await page.uncheck(tid('show-surfaces'));
  assert.equal((await page.evaluate(() => window.omnislice.voxel)).drawnTriangles, 0);
  await page.check(tid('show-surfaces'));
  await page.uncheck(tid('axis-glyphs-toggle'));
  await page.uncheck(tid('show-support'));
  const { name, text } = await downloadProgram();
  assert.equal(name, 'demo-overhang.gcode');
  assert.equal(text, out.program);
});

test('a real voxel slice of the demo at a coarse voxel width', async (t) => {
  if (skip(t)) return;
  await setSetting('setting-method', 'voxel');
  // A 3-axis machine cannot tilt the nozzle: the machine panel says so.
  assert.match(await page.textContent(tid('method-hint')), /choose table5, head4, head5 or a robot/);
  await setSetting('machine', 'table5');
  assert.equal(await page.isHidden(tid('method-hint')), true);
  await setSetting('voxel-width', 1.2);
  // The demo's voxel program is short of the soundness criteria (issue 25): written with a warning.
  await setSetting('setting-verify', 'warn');
  const before = await page.evaluate(() => Number(document.body.dataset.sliceCount || 0));
  const started = Date.now();
  await page.click(tid('slice-button'));
  await page.waitForFunction((n) => (document.body.dataset.state === 'done' && Number(document.body.dataset.sliceCount) > n)
    || document.body.dataset.state === 'error', before, { timeout: 180_000 });
  const state = await page.evaluate(() => document.body.dataset.state);
  if (state === 'error') {
    const message = await page.textContent(tid('error-message'));
    // Until the engine has the voxel method (issue 4's core pipeline), it refuses the setting.
    if (!IN_CI && /^invalid_option: setting 'method': 'voxel' is not available/.test(message)) {
      await setSetting('voxel-width', 0);
      await setSetting('setting-method', 'planar');
      await setSetting('machine', 'cartesian3');
      return t.skip(`the engine does not slice with method=voxel yet: ${message}`);
    }
    assert.fail(`voxel slice failed: ${message}`);
  }
  t.diagnostic(`voxel slice of the demo at 1.2 mm voxels: ${Date.now() - started} ms wall`);
  try {
    const stages = await page.evaluate(() => window.omnislice.stages.map(([s]) => s));
    for (const s of ['voxelize', 'peeling', 'growth', 'layers', 'toolpath', 'program']) assert.ok(stages.includes(s), `stage ${s} seen: ${stages}`);
    const listed = await page.$$eval(`${tid('stage-list')} li`, (els) => els.map((e) => e.dataset.stage));
    assert.deepEqual(listed, stages, 'the stage list shows every stage');
    const report = await page.evaluate(() => window.omnislice.report);
    const vr = report.voxel;
    assert.ok(vr && vr.voxels > 0 && vr.layers > 0 && vr.regions >= vr.layers, JSON.stringify(vr));
    t.diagnostic(`report.voxel: ${JSON.stringify({ ...vr, thickness: { ...vr.thickness, histogram: undefined } })}`);
    // The page sent only method and width: the core's other voxel values are the page's defaults.
    const coreSettings = report.settings || {};
    let compared = 0;
    for (const f of (await pageFields()).filter((x) => x.group === 'Voxel' && x.key !== 'voxel.width_mm')) {
      if (!(f.key in coreSettings)) continue;
      const core = coreSettings[f.key];
      if (typeof f.value === 'number') assert.ok(Math.abs(Number(core) - f.value) < 1e-9, `${f.key}: core ${core}, page ${f.value}`);
      else assert.equal(String(core), String(f.value), f.key);
      compared++;
    }
    t.diagnostic(`${compared} voxel defaults compared with report.settings`);
    assert.ok(compared >= 3, 'the report lists the voxel settings');
    assert.equal(Number(coreSettings['voxel.width_mm'] ?? 1.2), 1.2);
    assert.equal(await page.textContent(tid('voxel-voxels')), vr.voxels.toLocaleString('en'));
    assert.equal(await page.textContent(tid('missed-count')), vr.missed_voxels.toLocaleString('en'));
    assert.match(await page.textContent(tid('progress-text')),
      new RegExp(`done in [\\d.]+ s: ${vr.field_layers} field layers → ${vr.layers} layers, ${vr.regions} regions, ${vr.missed_voxels} missed`));
    const bars = await page.$$eval(`${tid('thickness-histogram')} rect.bar`, (els) => els.length);
    assert.equal(bars, vr.thickness.histogram.counts.length);
    assert.ok(bars > 0);
    const v = await page.evaluate(() => window.omnislice.voxel);
    assert.ok(v.surfaceTriangles > 0 && v.surfaceLayers > 1, JSON.stringify(v));
    if (vr.surface_layers !== undefined) assert.equal(v.surfaceLayers, vr.surface_layers, 'one surface layer per reported layer surface');
    assert.equal(v.drawnTriangles, v.surfaceTriangles);
    assert.equal(v.missed, vr.missed_voxels, 'one red cube per missed voxel');
    assert.ok(Math.abs(v.voxelWidth - vr.voxel_width_mm) < 1e-6);
    await slide('layer-surface-slider', Math.floor(v.surfaceLayers / 2));
    const half = await page.evaluate(() => window.omnislice.voxel);
    assert.ok(half.drawnTriangles > 0 && half.drawnTriangles < v.drawnTriangles, `half the layers: ${half.drawnTriangles} of ${v.drawnTriangles}`);
    await page.check(tid('axis-glyphs-toggle'));
    assert.ok((await page.evaluate(() => window.omnislice.voxel)).glyphsDrawn > 0, 'nozzle axis glyphs drawn');
    await page.waitForTimeout(400);
    await page.screenshot({ path: path.join(OUT_DIR, 'voxel-demo.png') });
    await page.locator(tid('voxel-report')).screenshot({ path: path.join(OUT_DIR, 'voxel-demo-report.png') });
    await page.uncheck(tid('axis-glyphs-toggle'));
    const { text } = await downloadProgram();
    const markers = (text.match(/^; omnislice:layer \d+/gm) || []).length;
    assert.equal(markers, report.layers, 'one layer marker per layer');
    assert.ok(text.length > 1000);
  } finally {
    await setSetting('voxel-width', 0);
    await setSetting('setting-verify', 'auto');
    await setSetting('setting-method', 'planar');
    await setSetting('machine', 'cartesian3');
  }
});

test('a planar slice afterwards hides the voxel view and figures', async (t) => {
  if (skip(t)) return;
  assert.equal(await page.evaluate(() => window.omnislice.settings.method), 'planar');
  const before = await page.evaluate(() => Number(document.body.dataset.sliceCount || 0));
  await page.click(tid('slice-button'), { timeout: 120_000 });
  await page.waitForFunction((n) => document.body.dataset.state === 'done' && Number(document.body.dataset.sliceCount) > n, before, { timeout: 180_000 });
  assert.equal(await page.isHidden(tid('voxel-bar')), true);
  assert.equal(await page.isHidden(tid('voxel-report')), true);
  assert.equal(await page.evaluate(() => window.omnislice.voxel), null);
  assert.doesNotMatch(await page.textContent(tid('progress-text')), /field layers/);
  const stages = await page.evaluate(() => window.omnislice.stages.map(([s]) => s));
  assert.ok(stages.includes('slice') && !stages.includes('growth'), stages.join(','));
});

test('a large voxel result is shown in short main-thread steps', async (t) => {
  if (skip(t)) return;
  // 300k surface triangles in 150 layers, 600k segments, 40k support and 2k missed cells. Every
  // app step after the result arrives (performance.measure 'omnislice:*': report, preview and
  // voxel-view blocks, sliders) must stay under 50 ms; the machine is shared, so up to three runs.
  const run = () => page.evaluate(async () => {
    const L = 150;
    const perLayer = 2000;
    const T = L * perLayer;
    const surfacePositions = new Float32Array(T * 9);
    for (let i = 0; i < T * 3; i++) {
      surfacePositions[3 * i] = (i * 7919) % 400 / 10;
      surfacePositions[3 * i + 1] = (i * 104729) % 400 / 10;
      surfacePositions[3 * i + 2] = Math.floor(i / (3 * perLayer)) * 0.3;
    }
    const surfaceTriangles = new Uint32Array(T * 3).map((_, i) => i);
    const surfaceLayers = new Uint32Array(T).map((_, k) => Math.floor(k / perLayer));
    const S = 600_000;
    const positions = new Float32Array(S * 6).map((_, i) => (i * 31) % 400 / 10);
    const features = new Uint8Array(S).map((_, k) => (k % 50 === 0 ? 0 : 4));
    const layers = new Uint32Array(S).map((_, k) => Math.floor((k * L) / S));
    const axes = new Float32Array(S * 3).map((_, i) => (i % 3 === 2 ? 1 : 0));
    const cells = (n) => new Float32Array(n * 3).map((_, i) => (i * 13) % 400 / 10);
    const r = {
      programBytes: new Uint8Array(16), programExtension: 'gcode',
      report: { layers: L, voxel: { voxels: 1e6, missed_voxels: 2000, layers: L, thickness: { histogram: { min_mm: 0, bin_mm: 0.05, counts: [3, 9, 4] } } } },
      preview: { positions, features, layers, machine: new Float32Array(S * 6), axes, surfacePositions, surfaceTriangles, surfaceLayers,
        missedVoxels: cells(2000), supportVoxels: cells(40_000), voxelWidth: 0.4 },
    };
    await new Promise((resolve) => requestAnimationFrame(() => setTimeout(resolve, 50)));
    const t0 = performance.now();
    await window.omnislice._showResultForTest(r);
    const wall = performance.now() - t0;
    const steps = performance.getEntriesByType('measure').filter((m) => m.name.startsWith('omnislice:') && m.startTime >= t0)
      .map((m) => ({ name: m.name, duration: m.duration }));
    return { wall, steps, voxel: window.omnislice.voxel };
  });
  for (let attempt = 1; attempt <= 3; attempt++) {
    const r = await run();
    const slow = r.steps.filter((x) => x.duration > 50);
    const longest = Math.max(0, ...r.steps.map((x) => x.duration));
    t.diagnostic(`run ${attempt}: shown in ${r.wall.toFixed(0)} ms, ${r.steps.length} steps, longest ${longest.toFixed(1)} ms`);
    assert.equal(r.voxel.surfaceTriangles, 300_000);
    assert.equal(r.voxel.missed, 2000);
    assert.equal(r.voxel.support, 40_000);
    assert.ok(r.voxel.glyphs > 1500 && r.voxel.glyphs <= 2001, `${r.voxel.glyphs} glyphs`);
    if (slow.length === 0) return;
    t.diagnostic(`slow steps: ${JSON.stringify(slow)}`);
  }
  assert.fail('every run had an app step over 50 ms (see diagnostics)');
});

test('no uncaught page error', (t) => {
  if (skip(t)) return;
  assert.deepEqual(pageErrors(), []);
});
