// SPDX-License-Identifier: MIT
// The geodesic method on the page (issue 6 item 9), in headless Chromium against the real worker
// and wasm module:
//   - the settings panel: the method choice shows the geodesic rows (interval, tet size or target
//     count, nozzle angle, sequence, remesh) and hides the planar-only ones; a 3-axis machine gets
//     the tilt hint;
//   - a synthetic geodesic result (report.geodesic and the preview's field, tree and sequence
//     buffers) shown through the page's test hook: the figures, the overhang chart (one point per
//     layer), the traversal table, the field drawn up to the layer slider's iso-value, the tree
//     and air moves following the layer range, the print step and the toggles;
//   - disagreeing buffers or report arrays: a clear error, the rest of the result still shown;
//   - the model menu's tree demo: loaded with the geodesic defaults on table5, sliced; the stages,
//     the field, the tree (one node per IGDS), the air moves (one per retraction), the chart and
//     the three traversals' figures show; choosing LPT in the table slices again with it (its
//     figures become the printed ones); the program downloads;
//   - a planar slice afterwards hides the geodesic view and report; no page errors.
// Screenshots go to build/e2e/geodesic-*.png.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import path from 'node:path';
import { OUT_DIR, appPage, tid } from './page-controls.mjs';

const { page, skip, pageErrors, setSetting, slide, sliceCount, waitSliced, sliceAndWait, downloadProgram } = appPage('geo');

test('the method choice shows the geodesic settings and hides the planar-only ones', async (t) => {
  if (skip(t)) return;
  const visible = (id) => page.isVisible(tid(id));
  const rows = ['geodesic-interval', 'geodesic-tet-size', 'geodesic-target-tets', 'geodesic-base-band', 'geodesic-max-thickness', 'geodesic-nozzle-angle', 'geodesic-sequence', 'geodesic-remesh'];
  for (const id of rows) assert.equal(await visible(id), false, `${id} hidden for planar`);
  await setSetting('setting-method', 'geodesic');
  for (const id of rows) assert.equal(await visible(id), true, `${id} shown for geodesic`);
  for (const id of ['setting-infill_pattern', 'setting-direction']) assert.equal(await visible(id), false, `${id} hidden`);
  for (const id of ['setting-infill', 'setting-walls']) assert.equal(await visible(id), true, `${id} shown (sparse curved layers)`);
  assert.equal(await visible('setting-layer_height'), true, 'the interval defaults to the layer height');
  assert.match(await page.textContent(tid('method-hint')), /geodesic method tilts the nozzle: choose table5, head4, head5 or a robot/);
  await setSetting('geodesic-tet-size', 1.5);
  assert.equal(await visible('geodesic-target-tets'), false, 'no target count with a tet size');
  await setSetting('geodesic-sequence', 'dpt');
  const settings = await page.evaluate(() => window.omnislice.settings);
  assert.equal(settings['geodesic.tet_size_mm'], 1.5);
  assert.equal(settings['geodesic.sequence'], 'dpt');
  await page.click(tid('settings-undo'));
  await page.click(tid('settings-undo'));
  assert.equal(await page.evaluate(() => window.omnislice.settings['geodesic.tet_size_mm']), 0, 'undone');
  await setSetting('setting-method', 'planar');
  assert.equal(await visible('geodesic-interval'), false);
  assert.equal(await page.isHidden(tid('method-hint')), true);
});

// A synthetic geodesic result built in the page: a cylinder's field (value = z), a fork tree of
// L = 12 layers (trunk 0..5, two branches 6..11), IGDS discs per node, a short tool-path per node.
function syntheticGeodesic({ L }) {
  const fieldPositions = [];
  const fieldValues = [];
  const fieldTriangles = [];
  for (let l = 0; l <= L; l++) {
    for (let k = 0; k < 16; k++) {
      const a = (k / 16) * 2 * Math.PI;
      fieldPositions.push(8 * Math.cos(a), 8 * Math.sin(a), l);
      fieldValues.push(l);
    }
  }
  for (let l = 0; l < L; l++) {
    for (let k = 0; k < 16; k++) {
      const a = 16 * l + k;
      const b = 16 * l + ((k + 1) % 16);
      fieldTriangles.push(a, b, b + 16, a, b + 16, a + 16);
    }
  }
  const nodePositions = [];
  const nodeLayers = [];
  const treeEdges = [];
  const fork = 6;
  for (let l = 0; l < L; l++) {
    if (l < fork) {
      nodePositions.push(0, 0, l + 1);
      nodeLayers.push(l);
      if (l) treeEdges.push(l - 1, l);
    } else {
      const n = nodePositions.length / 3;
      nodePositions.push(-4, 0, l + 1, 4, 0, l + 1);
      nodeLayers.push(l, l);
      const below = l === fork ? [fork - 1, fork - 1] : [n - 2, n - 1];
      treeEdges.push(below[0], n, below[1], n + 1);
    }
  }
  // A3-like: up the left branch, then the right one (one air move).
  const N = nodeLayers.length;
  const left = [];
  const right = [];
  for (let n = fork; n < N; n++) (((n - fork) % 2 === 0) ? left : right).push(n);
  const sequence = [...Array(fork).keys(), ...left, ...right];
  // IGDS surfaces: a small square per node; tool-path: one loop per node.
  const surfacePositions = [];
  const surfaceTriangles = [];
  const surfaceLayers = [];
  const positions = [];
  const features = [];
  const layers = [];
  const axes = [];
  const machine = [];
  for (const n of sequence) {
    const [x, y, z] = nodePositions.slice(3 * n, 3 * n + 3);
    const r = n < fork ? 6 : 3;
    const v = surfacePositions.length / 3;
    surfacePositions.push(x - r, y - r, z, x + r, y - r, z, x + r, y + r, z, x - r, y + r, z);
    surfaceTriangles.push(v, v + 1, v + 2, v, v + 2, v + 3);
    surfaceLayers.push(nodeLayers[n], nodeLayers[n]);
    let prev = null;
    for (let k = 0; k <= 24; k++) {
      const a = (k / 24) * 2 * Math.PI;
      const p = [x + 0.8 * r * Math.cos(a), y + 0.8 * r * Math.sin(a), z];
      if (prev) {
        positions.push(...prev, ...p);
        features.push(k === 1 ? 0 : 4);
        layers.push(nodeLayers[n]);
        axes.push(0, 0, 1);
        machine.push(...p, 0, 0, 0);
      }
      prev = p;
    }
  }
  const avg = Array.from({ length: L }, (_, l) => (l === 0 ? 0 : 10 + 40 * Math.sin((l / L) * Math.PI)));
  const ratio = avg.map((x) => Math.min(1, x / 90));
  const report = {
    method: 'geodesic', layers: L, path_mm: 800, extrusion_mm: 30, estimated_time_s: 240, timings_ms: { total: 3000 },
    program_format: 'gcode', machine: 'table5', machine_kind: 'table5',
    warnings: [{ code: 'skipped_tool_path', message: '3 mm of tool path left out on layers 11-12 of 12' }],
    geodesic: {
      tets: 23456, tet_source: 'mesher', max_geodesic_mm: L, interval_mm: 1, layers: L, igds: N,
      iso_values_mm: Array.from({ length: L }, (_, l) => l + 1),
      tree: { nodes: N, edges: treeEdges.length / 2, is_tree: true, branch_points: 1, merges: 0 },
      sequence: 'A3', retractions: 1, air_move_mm: Math.hypot(8, L - fork - 1), collision_free: true, nozzle_angle_deg: 45,
      overhang_avg_deg: avg, overhang_ratio: ratio, overhang_avg_all_deg: 30, overhang_max_layer_deg: 50,
      thickness: { max_deviation_all_percent: 20 }, paths: N, skipped_segments: 2, skipped_mm: 3, skipped_layers: [10, 11],
      traversals: {
        LPT: { retractions: 11, air_move_mm: 88, collision_free: true, colliding_nodes: 0 },
        DPT: { retractions: 1, air_move_mm: Math.hypot(8, L - fork - 1), collision_free: false, colliding_nodes: 2 },
        A3: { retractions: 1, air_move_mm: Math.hypot(8, L - fork - 1), collision_free: true, colliding_nodes: 0 },
      },
      timings_ms: { tetmesh: 300, field: 500, igds: 400, tree: 5, collision: 30, paths: 60, toolpath: 20 },
    },
  };
  const program = `; synthetic geodesic program\n${sequence.map((n) => `; omnislice:layer ${nodeLayers[n]}\nG1 X0 Y0 Z1 E1\n`).join('')}`;
  return {
    programBytes: new TextEncoder().encode(program),
    programExtension: 'gcode',
    report,
    preview: {
      positions: new Float32Array(positions), features: new Uint8Array(features), layers: new Uint32Array(layers),
      machine: new Float32Array(machine), axes: new Float32Array(axes),
      surfacePositions: new Float32Array(surfacePositions), surfaceTriangles: new Uint32Array(surfaceTriangles),
      surfaceLayers: new Uint32Array(surfaceLayers), missedVoxels: new Float32Array(0), supportVoxels: new Float32Array(0), voxelWidth: 0,
      curves: new Uint32Array(0),
      fieldPositions: new Float32Array(fieldPositions), fieldTriangles: new Uint32Array(fieldTriangles), fieldValues: new Float32Array(fieldValues),
      nodePositions: new Float32Array(nodePositions), nodeLayers: new Uint32Array(nodeLayers), treeEdges: new Uint32Array(treeEdges),
      sequence: new Uint32Array(sequence), skippedSegments: new Float32Array([-4, 0, L - 1, -3, 0, L - 1, -3, 0, L - 1, -1, 0, L]),
      skippedLayers: new Uint32Array([L - 2, L - 1]),
    },
    program,
  };
}

test('a synthetic geodesic result: figures, chart, traversals, field, tree, air moves, sliders', async (t) => {
  if (skip(t)) return;
  const L = 12;
  await page.evaluate(async ([fnText, args]) => {
    // eslint-disable-next-line no-new-func
    const make = new Function(`return (${fnText})`)();
    await window.omnislice._showResultForTest(make(args));
  }, [syntheticGeodesic.toString(), { L }]);
  assert.equal(await page.evaluate(() => document.body.dataset.state), 'done');
  assert.equal(await page.isVisible(tid('geo-report')), true);
  assert.equal(await page.textContent(tid('geo-tets')), '23,456');
  assert.equal(await page.textContent(tid('geo-layers')), '12');
  assert.equal(await page.textContent(tid('geo-collision_free')), 'yes');
  assert.equal(await page.textContent(tid('geo-time_field')), '500 ms');
  // The tool path left out: the warning under the result, the summary row, red lines in the view.
  assert.deepEqual(await page.$$eval(`${tid('report-warnings')} li`, (lis) => lis.map((li) => [li.dataset.code, li.textContent])),
    [['skipped_tool_path', '3 mm of tool path left out on layers 11-12 of 12']]);
  assert.equal(await page.textContent(tid('geo-skipped')), '3 mm (2 segments), layers 11–12');
  assert.deepEqual(await page.evaluate(() => [window.omnislice.geodesic.skipped, window.omnislice.geodesic.skippedDrawn]), [2, 2]);
  assert.match(await page.textContent(tid('progress-text')), /done in [\d.]+ s: 23,456 tets → 12 layers, 18 IGDS; A3: 1 retractions, [\d.]+ mm air, collision-free/);
  // The chart: one point per layer, ratio bars, the mark at the layer slider's top layer.
  const chart = await page.evaluate(() => {
    const svg = document.querySelector('[data-testid="geo-overhang-chart"]');
    return { ...svg.dataset, dots: svg.querySelectorAll('circle.dot').length, over: svg.querySelectorAll('circle.dot.over').length };
  });
  assert.equal(chart.layers, String(L));
  assert.equal(chart.points, String(L));
  assert.equal(chart.dots, L);
  assert.equal(chart.bars, String(L));
  assert.equal(chart.over, 3, 'layers 6-8 (10 + 40 sin(l pi / 12) > 45) marked');
  assert.equal(await page.textContent(tid('geo-chart-stats')), '12 layers, largest 50°, 3 above 45°');
  assert.equal(chart.layer, String(L - 1));
  // The traversal table: the three sequences, A3 printed, DPT flagged.
  const rows = await page.$$eval(`${tid('geo-traversal-table')} tbody tr`, (trs) => trs.map((tr) => ({
    id: tr.dataset.testid, chosen: tr.classList.contains('chosen'), retractions: tr.dataset.retractions, free: tr.dataset.collisionFree,
    button: !!tr.querySelector('button'),
  })));
  assert.deepEqual(rows.map((r) => [r.id, r.chosen, r.retractions, r.free, r.button]), [
    ['geo-traversal-LPT', false, '11', 'true', true], ['geo-traversal-DPT', false, '1', 'false', true], ['geo-traversal-A3', true, '1', 'true', false]]);
  // The table fits the panel (no clipped column).
  const fit = await page.evaluate(() => {
    const box = (id) => document.querySelector(`[data-testid="${id}"]`).getBoundingClientRect();
    return { table: box('geo-traversal-table').right, panel: box('geo-report').right };
  });
  assert.ok(fit.table <= fit.panel + 0.5, `table right ${fit.table} within the panel ${fit.panel}`);
  // The view: everything at the last layer; the field follows the layer slider's iso-value.
  assert.equal(await page.isVisible(tid('geo-bar')), true);
  assert.equal(await page.isVisible(tid('show-missed')), false, 'no missed cells for this method');
  let g = await page.evaluate(() => window.omnislice.geodesic);
  assert.equal(g.nodes, 18);
  assert.equal(g.nodesDrawn, 18);
  assert.equal(g.edges, 17);
  assert.equal(g.airMoves, 1, 'one air move: from the left tip to the right fork');
  assert.equal(g.fieldTriangles, 32 * L);
  assert.equal(g.fieldDrawn, 32 * L);
  assert.equal(await page.textContent(tid('air-count')), '1');
  assert.equal(await page.textContent(tid('field-range')), `0–${L} mm`);
  for (const hi of [0, 3, 8]) {
    await slide('layer-slider', hi);
    g = await page.evaluate(() => window.omnislice.geodesic);
    // iso-value of layer hi is hi + 1: the bands j with j + 1 <= hi + 1.
    assert.equal(g.fieldDrawn, 32 * (hi + 1), `field up to layer ${hi}`);
    assert.equal(g.nodesDrawn, hi < 6 ? hi + 1 : 6 + 2 * (hi - 5), `nodes of layers 0..${hi}`);
    assert.equal(g.skippedDrawn, 0, 'the skipped path lies on the last two layers');
    assert.equal(await page.evaluate(() => document.querySelector('[data-testid="geo-overhang-chart"]').dataset.layer), String(hi));
    assert.equal(await page.inputValue(tid('layer-surface-slider')), String(hi), 'the IGDS surfaces follow');
  }
  await slide('layer-slider', L - 1);
  // The print step: up the left branch first.
  await slide('geo-step-slider', 11);
  g = await page.evaluate(() => window.omnislice.geodesic);
  assert.equal(g.nodesDrawn, 12);
  assert.equal(g.airDrawn, 0, 'the air move comes later');
  assert.equal(g.current.layer, 11);
  assert.match(await page.textContent(tid('geo-step-text')), /^12 of 18 \(layer 12\)$/);
  await slide('geo-step-slider', 12);
  g = await page.evaluate(() => window.omnislice.geodesic);
  assert.equal(g.airDrawn, 1);
  assert.equal(g.current.layer, 6);
  await page.uncheck(tid('show-field'));
  await page.uncheck(tid('show-air'));
  g = await page.evaluate(() => window.omnislice.geodesic);
  assert.equal(g.fieldDrawn + g.airDrawn, 0);
  await page.check(tid('show-field'));
  await page.check(tid('show-air'));
  await slide('geo-step-slider', 17);
  await page.waitForTimeout(300);
  await page.screenshot({ path: path.join(OUT_DIR, 'geodesic-synthetic.png') });
});

test('a result with disagreeing geodesic buffers: a clear error, the rest still shown', async (t) => {
  if (skip(t)) return;
  const out = await page.evaluate(async ([fnText, args]) => {
    // eslint-disable-next-line no-new-func
    const make = new Function(`return (${fnText})`)();
    const r = make(args);
    r.preview.sequence = r.preview.sequence.subarray(0, 5);
    r.report.geodesic.overhang_ratio = [0.5];
    await window.omnislice._showResultForTest(r);
    return { state: document.body.dataset.state, geodesic: window.omnislice.geodesic, segments: window.omnislice.previewSegments };
  }, [syntheticGeodesic.toString(), { L: 12 }]);
  assert.equal(out.state, 'done');
  assert.equal(out.geodesic, null, 'no geodesic view from bad buffers');
  assert.ok(out.segments > 0, 'the tool-paths still drawn');
  assert.equal(await page.textContent(tid('error-message')), 'internal: geodesic view: geodesic buffers: the sequence has 5 entries for 18 nodes');
  assert.equal(await page.isHidden(tid('geo-bar')), true);
  assert.equal(await page.textContent(tid('geo-chart-stats')), '(overhang chart: 1 overhang ratios for 12 layers)');
  assert.equal(await page.textContent(tid('geo-tets')), '23,456', 'the figures still shown');
});

test('the tree demo: geodesic slice, field, tree, air moves, chart, traversal switch, download', async (t) => {
  if (skip(t)) return;
  const before = await sliceCount();
  const started = Date.now();
  await page.selectOption(tid('demo-model'), 'tree');
  const failed = await waitSliced(before);
  if (failed) assert.fail(`tree demo slice failed: ${failed}`);
  t.diagnostic(`tree demo loaded and sliced in ${Date.now() - started} ms`);
  const settings = await page.evaluate(() => window.omnislice.settings);
  assert.equal(settings.method, 'geodesic');
  assert.equal(settings.machine, 'table5');
  assert.equal(settings.nozzle, 0.8);
  assert.equal(settings['geodesic.interval_mm'], 0.8);
  assert.equal(settings['geodesic.nozzle_angle_deg'], 45);
  assert.equal(await page.textContent(tid('model-name')), 'demo-tree.obj');
  assert.equal(await page.textContent(tid('info-closed')), 'yes');
  const stages = await page.evaluate(() => window.omnislice.stages.map(([s]) => s));
  for (const s of ['tetmesh', 'field', 'igds', 'collision', 'paths', 'toolpath', 'program']) assert.ok(stages.includes(s), `stage ${s}: ${stages}`);
  const report = await page.evaluate(() => window.omnislice.report);
  const geo = report.geodesic;
  assert.ok(geo && geo.tets > 0 && geo.layers > 10 && geo.igds >= geo.layers, JSON.stringify({ ...geo, overhang_avg_deg: undefined }));
  assert.equal(geo.sequence, 'A3');
  assert.equal(geo.nozzle_angle_deg, 45);
  t.diagnostic(`${geo.tets} tets, ${geo.layers} layers, ${geo.igds} IGDS; traversals ${JSON.stringify(geo.traversals)}`);
  // A3 collides on no more IGDS than every order must (colliding_lower_bound). Since the field's
  // changes of 2026-11-27 one IGDS of the demo holds its own ancestor in its cone at every angle
  // from 35 to 45 deg (an unavoidable collision), natively and in wasm alike.
  assert.equal(geo.traversals.A3.colliding_nodes, geo.traversals.A3.colliding_lower_bound, 'A3 reaches the lower bound on the demo');
  assert.ok(geo.traversals.A3.retractions < geo.traversals.LPT.retractions, 'with fewer retractions than LPT');
  // The view holds the report's tree; the air moves drawn are its retractions.
  let g = await page.evaluate(() => window.omnislice.geodesic);
  assert.equal(g.nodes, geo.igds);
  assert.equal(g.edges, geo.tree.edges);
  assert.equal(g.airMoves, geo.retractions);
  assert.ok(Math.abs(g.airMoveMm - geo.air_move_mm) < 1e-3 * Math.max(1, geo.air_move_mm), `${g.airMoveMm} vs ${geo.air_move_mm}`);
  assert.ok(g.fieldTriangles > 1000 && g.fieldDrawn === g.fieldTriangles, JSON.stringify(g));
  assert.ok(Math.abs(g.fieldMax - geo.max_geodesic_mm) < 0.1 * geo.max_geodesic_mm);
  assert.equal(await page.textContent(tid('air-count')), String(geo.retractions));
  const v = await page.evaluate(() => window.omnislice.voxel);
  assert.ok(v.surfaceLayers > 10 && v.surfaceTriangles > 0, 'the IGDS drawn as layer surfaces');
  // The chart: one point per layer; the figures.
  assert.equal(await page.evaluate(() => document.querySelector('[data-testid="geo-overhang-chart"]').dataset.points), String(geo.layers));
  assert.equal(await page.textContent(tid('geo-igds')), geo.igds.toLocaleString('en'));
  const table = async () => page.$$eval(`${tid('geo-traversal-table')} tbody tr`, (trs) => Object.fromEntries(trs.map((tr) => [
    tr.dataset.testid.replace('geo-traversal-', ''), { retractions: Number(tr.dataset.retractions), free: tr.dataset.collisionFree === 'true', chosen: tr.classList.contains('chosen') }])));
  const rows = await table();
  for (const name of ['LPT', 'DPT', 'A3']) {
    assert.equal(rows[name].retractions, geo.traversals[name].retractions, `${name} retractions shown`);
    assert.equal(rows[name].free, geo.traversals[name].collision_free, `${name} collision verdict shown`);
  }
  assert.equal(rows.A3.chosen, true);
  // Halfway up: the field and the tree are cut at that layer.
  const mid = Math.floor(geo.layers / 2);
  await slide('layer-slider', mid);
  g = await page.evaluate(() => window.omnislice.geodesic);
  assert.ok(g.fieldDrawn > 0 && g.fieldDrawn < g.fieldTriangles, `field to layer ${mid}: ${g.fieldDrawn} of ${g.fieldTriangles}`);
  assert.ok(g.nodesDrawn > 0 && g.nodesDrawn < g.nodes);
  await slide('layer-slider', geo.layers - 1);
  await page.waitForTimeout(400);
  await page.screenshot({ path: path.join(OUT_DIR, 'geodesic-tree.png') });
  await page.locator(tid('geo-report')).screenshot({ path: path.join(OUT_DIR, 'geodesic-tree-report.png') });
  // Choose LPT in the table: a new slice with that sequence; its figures become the printed ones.
  const lpt = geo.traversals.LPT;
  const before2 = await sliceCount();
  await page.click(tid('geo-use-LPT'));
  const failed2 = await waitSliced(before2);
  if (failed2) assert.fail(`LPT slice failed: ${failed2}`);
  assert.equal(await page.evaluate(() => window.omnislice.settings['geodesic.sequence']), 'lpt');
  const geo2 = (await page.evaluate(() => window.omnislice.report)).geodesic;
  assert.equal(geo2.sequence, 'LPT');
  assert.equal(geo2.retractions, lpt.retractions);
  g = await page.evaluate(() => window.omnislice.geodesic);
  assert.equal(g.airMoves, lpt.retractions, 'the air moves of LPT drawn');
  assert.equal((await table()).LPT.chosen, true);
  await page.waitForTimeout(400);
  await page.screenshot({ path: path.join(OUT_DIR, 'geodesic-tree-lpt.png') });
  // The program.
  const { name, text } = await downloadProgram();
  assert.equal(name, 'demo-tree.gcode');
  assert.ok(text.length > 10_000, `${text.length} bytes`);
  const markers = new Set((text.match(/^; omnislice:layer \d+/gm) || []).map((m) => m.split(' ').pop()));
  assert.equal(markers.size, geo2.printed_layers ?? geo2.layers, 'every printed layer has its marker');
});

test('a planar slice afterwards hides the geodesic view and report', async (t) => {
  if (skip(t)) return;
  await setSetting('setting-method', 'planar');
  await setSetting('machine', 'cartesian3');
  const failed = await sliceAndWait();
  if (failed) assert.fail(`planar slice failed: ${failed}`);
  assert.equal(await page.isHidden(tid('geo-bar')), true);
  assert.equal(await page.isHidden(tid('geo-report')), true);
  assert.equal(await page.evaluate(() => window.omnislice.geodesic), null);
  assert.equal(await page.isVisible(tid('show-missed')), false, 'no voxel bar either');
  // The geodesic warning is gone; what the planar slice says (auto supports under the tree's
  // overhangs) is its own.
  const notes = await page.$$eval(`${tid('report-warnings')} li`, (lis) => lis.map((li) => li.textContent));
  const codes = (await page.evaluate(() => window.omnislice.report)).warnings.map((w) => w.code);
  assert.ok(codes.every((c) => c === 'supports_added'), `planar warnings: ${codes}`);
  assert.equal(notes.length, codes.length, `the earlier warning is gone: ${notes}`);
});

test('no uncaught page error', (t) => {
  if (skip(t)) return;
  assert.deepEqual(pageErrors(), []);
});
