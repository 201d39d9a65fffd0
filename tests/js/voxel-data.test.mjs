// SPDX-License-Identifier: MIT
// The voxel view's data preparation (web/methods/voxel-data.js) against direct computations: layer
// surfaces de-indexed and sorted by layer with the right vertices and colours, slider ranges
// covering exactly the chosen layers' triangles, glyph decimation (count bound, spacing, glyph
// geometry along the axis, layer order), the histogram's bar geometry and the voxel summary rows.
// Also the settings schema's voxel rows (shown only for the voxel method, only changed values
// sent).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import {
  buildSurfaceArrays, decimateGlyphs, glyphRange, histogramGeometry, layerColor,
  surfaceRanges, voxelDoneSummary, voxelSummaryRows,
} from '../../web/methods/voxel-data.js';
import { fieldsUnavailable, pageFields } from './page-settings.mjs';
import { SettingsModel } from '../../web/settings-panel.js';

function rng(seed) {
  let x = seed;
  return () => ((x = (x * 1103515245 + 12345) % 2147483648) / 2147483648);
}

// A random triangle soup: V vertices, T triangles with random layers in 0..L-1.
function makeSurfaces(V, T, L, seed = 5) {
  const rnd = rng(seed);
  const surfacePositions = new Float32Array(V * 3).map(() => rnd() * 50);
  const surfaceTriangles = new Uint32Array(T * 3).map(() => Math.floor(rnd() * V));
  const surfaceLayers = new Uint32Array(T).map(() => Math.floor(rnd() * L));
  return { surfacePositions, surfaceTriangles, surfaceLayers };
}

test('buildSurfaceArrays de-indexes the soup and sorts it by layer, stably, with layer colours', async () => {
  const p = makeSurfaces(3000, 20_000, 37);
  const a = await buildSurfaceArrays(p, { block: 500, budgetMs: 0 });
  const L = Math.max(...p.surfaceLayers) + 1;
  assert.equal(a.layerCount, L);
  assert.equal(a.triangleCount, 20_000);
  // Expected order: triangles of layer 0 in soup order, then layer 1, ...
  const order = [];
  for (let l = 0; l < L; l++) {
    assert.equal(a.starts[l], order.length, `start of layer ${l}`);
    for (let t = 0; t < p.surfaceLayers.length; t++) if (p.surfaceLayers[t] === l) order.push(t);
  }
  assert.equal(a.starts[L], order.length);
  for (let k = 0; k < order.length; k += 7) {
    const t = order[k];
    assert.equal(a.layers[k], p.surfaceLayers[t]);
    for (let c = 0; c < 3; c++) {
      const v = p.surfaceTriangles[3 * t + c];
      assert.deepEqual([...a.positions.subarray(9 * k + 3 * c, 9 * k + 3 * c + 3)], [...p.surfacePositions.subarray(3 * v, 3 * v + 3)]);
      assert.deepEqual([...a.colors.subarray(9 * k + 3 * c, 9 * k + 3 * c + 3)], layerColor(p.surfaceLayers[t], L));
    }
  }
  await assert.rejects(buildSurfaceArrays({ ...p, surfaceLayers: p.surfaceLayers.subarray(1) }), /disagree/);
  const bad = { ...p, surfaceTriangles: p.surfaceTriangles.slice() };
  bad.surfaceTriangles[300] = 3000;
  await assert.rejects(buildSurfaceArrays(bad), /triangle 100 refers to a vertex beyond/);
  const none = await buildSurfaceArrays({});
  assert.equal(none.layerCount, 0);
  assert.equal(none.triangleCount, 0);
});

test('layer colours: adjacent layers differ, first blue-ish and last red-ish', () => {
  const L = 50;
  for (let l = 0; l + 1 < L; l++) {
    const [a, b] = [layerColor(l, L), layerColor(l + 1, L)];
    assert.ok(Math.abs(a[0] - b[0]) + Math.abs(a[1] - b[1]) + Math.abs(a[2] - b[2]) > 20, `layers ${l} and ${l + 1}`);
    for (const c of a) assert.ok(Number.isInteger(c) && c >= 0 && c <= 255);
  }
  const first = layerColor(0, L);
  const last = layerColor(L - 1, L);
  assert.ok(first[2] > first[0], `first ${first}`);
  assert.ok(last[0] > last[2], `last ${last}`);
});

test('surfaceRanges: layers lo..hi-1 below, layer hi current, exactly their triangles', async () => {
  const p = makeSurfaces(500, 6000, 20, 9);
  const a = await buildSurfaceArrays(p);
  const count = (lo, hi) => p.surfaceLayers.filter((l) => l >= lo && l <= hi).length;
  for (const [lo, hi] of [[0, 19], [0, 0], [0, 10], [5, 12], [19, 19], [12, 3], [-4, 99]]) {
    const r = surfaceRanges(a.starts, lo, hi);
    assert.equal(r.below.count, r.hi > r.lo ? count(r.lo, r.hi - 1) : 0, `below ${lo}..${hi}`);
    assert.equal(r.current.count, count(r.hi, r.hi), `current ${lo}..${hi}`);
    assert.equal(r.current.start, r.below.start + r.below.count, 'contiguous');
    for (let k = r.below.start; k < r.current.start + r.current.count; k++) {
      assert.ok(a.layers[k] >= r.lo && a.layers[k] <= r.hi);
    }
  }
  assert.deepEqual([surfaceRanges(a.starts, -4, 99).lo, surfaceRanges(a.starts, -4, 99).hi], [0, 19]);
  assert.deepEqual([surfaceRanges(a.starts, 12, 3).lo, surfaceRanges(a.starts, 12, 3).hi], [12, 12]);
  const empty = surfaceRanges(new Uint32Array(1), 0, 5);
  assert.equal(empty.current.count + empty.below.count, 0);
});

// A tool-path preview: S segments in L layers, a polyline with travel every 10th segment.
function makeToolpath(S, L, seed = 3) {
  const rnd = rng(seed);
  const positions = new Float32Array(S * 6);
  const features = new Uint8Array(S);
  const layers = new Uint32Array(S);
  const axes = new Float32Array(S * 3);
  let p = [0, 0, 0];
  for (let s = 0; s < S; s++) {
    const q = [p[0] + rnd() - 0.5, p[1] + rnd() - 0.5, p[2] + rnd() * 0.1];
    positions.set([...p, ...q], 6 * s);
    p = q;
    features[s] = s % 10 === 9 ? 0 : 1 + Math.floor(rnd() * 4);
    layers[s] = Math.floor((s * L) / S);
    const a = [rnd() - 0.5, rnd() - 0.5, 1];
    const n = Math.hypot(...a);
    axes.set(a.map((x) => x / n), 3 * s);
  }
  return { positions, features, layers, axes };
}

test('decimateGlyphs: at most maxGlyphs+1 glyphs, evenly spaced, along the axes, sorted by layer', async () => {
  const p = makeToolpath(30_000, 25);
  const g = await decimateGlyphs(p, { maxGlyphs: 500, length: 2, block: 1000, budgetMs: 0 });
  assert.ok(g.count >= 480 && g.count <= 501, `${g.count} glyphs`);
  assert.equal(g.layerCount, 25);
  const segLen = (s) => Math.hypot(p.positions[6 * s + 3] - p.positions[6 * s], p.positions[6 * s + 4] - p.positions[6 * s + 1], p.positions[6 * s + 5] - p.positions[6 * s + 2]);
  let total = 0;
  for (let s = 0; s < p.features.length; s++) if (p.features[s] !== 0) total += segLen(s);
  assert.ok(Math.abs(g.spacing - total / 500) < 1e-6 * total);
  for (let k = 0; k < g.count; k++) {
    const s = g.segments[k];
    assert.notEqual(p.features[s], 0, 'glyphs only on printing segments');
    assert.equal(g.layers[k], p.layers[s]);
    if (k > 0) assert.ok(g.layers[k] >= g.layers[k - 1], 'sorted by layer');
    const start = [...g.positions.subarray(6 * k, 6 * k + 3)];
    const end = [...g.positions.subarray(6 * k + 3, 6 * k + 6)];
    for (let c = 0; c < 3; c++) {
      assert.equal(start[c], p.positions[6 * s + 3 + c], 'starts at the segment end');
      assert.ok(Math.abs(end[c] - start[c] - 2 * p.axes[3 * s + c]) < 1e-4, 'along the axis, 2 mm');
    }
  }
  // Spacing: the printed length between consecutive glyphs (in print order) is about the spacing.
  const picked = [...g.segments].sort((a, b) => a - b);
  const walked = [];
  let acc = 0;
  let j = 0;
  for (let s = 0; s < p.features.length && j < picked.length; s++) {
    if (p.features[s] !== 0) acc += segLen(s);
    if (s === picked[j]) {
      walked.push(acc);
      j++;
    }
  }
  for (let i = 1; i < walked.length; i++) {
    const gap = walked[i] - walked[i - 1];
    assert.ok(gap > 0 && gap < 2 * g.spacing + 1, `gap ${gap} vs spacing ${g.spacing}`);
  }
  // Per-layer starts and the layer range.
  for (let l = 0; l < 25; l++) {
    for (let k = g.starts[l]; k < g.starts[l + 1]; k++) assert.equal(g.layers[k], l);
  }
  const r = glyphRange(g.starts, 5, 9);
  assert.equal(r.count, [...g.layers].filter((l) => l >= 5 && l <= 9).length);
  assert.equal(glyphRange(g.starts, -1, 1e9).count, g.count);
  // No axes (planar result), zero axes or mismatched buffers: no glyphs.
  assert.equal((await decimateGlyphs({ ...p, axes: new Float32Array(0) })).count, 0);
  assert.equal((await decimateGlyphs({ ...p, axes: new Float32Array(p.axes.length) })).count, 0);
  assert.equal((await decimateGlyphs({ ...p, axes: p.axes.subarray(3) })).count, 0);
  // Everything kept when the spacing is tiny.
  const all = await decimateGlyphs(p, { spacing: 1e-9 });
  assert.equal(all.count, p.features.filter((f) => f !== 0).length);
});

test('histogramGeometry: bars proportional to counts, spanning the plot, ticks in mm', () => {
  const hist = { min_mm: -0.12, bin_mm: 0.02, counts: [1, 4, 10, 25, 40, 22, 8, 0, 2, 0, 1, 0] };
  const g = histogramGeometry(hist, { width: 260, height: 110, padLeft: 6, padRight: 6, padTop: 6, padBottom: 18, ticks: 4 });
  assert.equal(g.bars.length, 12);
  assert.equal(g.total, 113);
  assert.equal(g.maxCount, 40);
  assert.deepEqual(g.plot, { x: 6, y: 6, width: 248, height: 86 });
  for (const [i, b] of g.bars.entries()) {
    assert.ok(Math.abs(b.height - (hist.counts[i] / 40) * 86) < 1e-9);
    assert.ok(Math.abs(b.y + b.height - 92) < 1e-9, 'bars stand on the base line');
    assert.ok(Math.abs(b.x - (6 + (i * 248) / 12)) < 1e-9);
    assert.ok(Math.abs(b.from - (-0.12 + i * 0.02)) < 1e-12 && Math.abs(b.to - b.from - 0.02) < 1e-12);
  }
  assert.equal(g.bars[4].height, 86, 'the tallest bar fills the plot');
  // Span -0.12..0.12 mm, about 4 ticks: every 0.1 mm (0.06 rounded up to 1-2-5 steps).
  assert.deepEqual(g.ticks.map((t) => t.label), ['-0.1', '0', '0.1']);
  for (const tk of g.ticks) assert.ok(Math.abs(tk.x - (6 + ((tk.value + 0.12) / 0.24) * 248)) < 1e-9, `tick ${tk.label} at ${tk.x}`);
  const wide = histogramGeometry({ min_mm: -0.895, bin_mm: 0.1, counts: new Array(76).fill(1) }, { ticks: 5 });
  assert.deepEqual(wide.ticks.map((t) => t.label), ['0', '2', '4', '6']);
  assert.equal(histogramGeometry({ min_mm: 0, bin_mm: 1, counts: [0, 0] }).bars.every((b) => b.height === 0), true);
  assert.equal(histogramGeometry({ min_mm: 0, bin_mm: 1, counts: [] }).bars.length, 0);
  assert.throws(() => histogramGeometry({ min_mm: 0, bin_mm: 0, counts: [1] }), /bin_mm/);
  assert.throws(() => histogramGeometry({ min_mm: 'x', bin_mm: 1, counts: [1] }), /min_mm/);
  assert.throws(() => histogramGeometry({ min_mm: 0, bin_mm: 1, counts: [1, -2] }), /counts/);
  assert.throws(() => histogramGeometry(null), /missing/);
});

test('voxel summary rows and the done line show the report\'s figures', () => {
  const v = {
    voxels: 77064, solid_voxels: 70000, support_voxels: 120, missed_voxels: 511, field_layers: 240, layers: 96, regions: 130,
    strategy: 'pg-sp-gcfa', shadow_scheme: 'recursive', voxel_width_mm: 0.32, iso_step: 0.8,
    thickness: { samples: 1000, mean_mm: 0.3012, std_mm: 0.041, max_deviation_mm: 0.155, histogram: { min_mm: 0, bin_mm: 0.05, counts: [1] } },
    timings_ms: { voxelize: 120.4, peeling: 2300, shadow: 800, growth: 4100, extraction: 900, toolpaths: 1500 },
    shadow_checks: 123456, hull_builds: 240, orientation_fallbacks: 0,
  };
  const rows = Object.fromEntries(voxelSummaryRows(v).map(([k, , text]) => [k, text]));
  assert.equal(rows.voxels, '77,064');
  assert.equal(rows.missed_voxels, '511');
  assert.equal(rows.strategy, 'pg-sp-gcfa');
  assert.equal(rows.voxel_width_mm, '0.32 mm');
  assert.equal(rows.thickness_mean, '0.301 mm');
  assert.equal(rows.time_peeling, '2.30 s');
  assert.equal(rows.time_voxelize, '120 ms');
  assert.equal(rows.orientation_fallbacks, '0');
  assert.equal(rows.axes_freed, undefined, 'no row without the figure');
  const freed = Object.fromEntries(voxelSummaryRows({ ...v, axes_freed: 12345, axis_freedom_deg: 15 }).map(([k, , text]) => [k, text]));
  assert.equal(freed.axes_freed, '12,345 (≤ 15°)');
  assert.equal(voxelDoneSummary(v), '240 field layers → 96 layers, 130 regions, 511 missed');
  const blank = Object.fromEntries(voxelSummaryRows(null).map(([k, , text]) => [k, text]));
  assert.ok(Object.values(blank).every((t) => t === '—'));
});

test('settings: voxel rows only for the voxel method; planar-only rows hidden for it; only changes sent', { skip: fieldsUnavailable }, async () => {
  const fields = await pageFields();
  const model = new SettingsModel(fields);
  const showIf = (key) => {
    const f = fields.find((x) => x.key === key);
    return f.showIf ? f.showIf(model.values) : true;
  };
  const voxelKeys = fields.filter((f) => f.group === 'Voxel').map((f) => f.key);
  assert.deepEqual(voxelKeys.sort(), ['voxel.epsilon', 'voxel.iso_step', 'voxel.layer_field', 'voxel.layer_mm', 'voxel.max_thickness_ratio', 'voxel.max_tilt_deg',
    'voxel.max_voxels', 'voxel.peel_step', 'voxel.platform_radius_mm', 'voxel.shadow', 'voxel.smooth', 'voxel.strategy', 'voxel.supports',
    'voxel.width_mm'].sort());
  assert.ok(voxelKeys.every((k) => !showIf(k)), 'hidden for planar');
  assert.equal(showIf('infill'), true);
  model.set('method', 'voxel');
  assert.ok(voxelKeys.every((k) => showIf(k)), 'shown for voxel (PG-SP-GCFA)');
  for (const k of ['infill_pattern', 'layer_height', 'direction']) assert.equal(showIf(k), false, `${k} hidden for voxel`);
  // The shell and the interior's density reach curved layers too.
  for (const k of ['infill', 'walls', 'top_layers', 'bottom_layers']) assert.equal(showIf(k), true, `${k} shown for voxel`);
  assert.equal(showIf('nozzle'), true);
  model.set('voxel.strategy', 'gcfa');
  assert.equal(showIf('voxel.shadow'), false, 'no shadow prevention in plain GCFA');
  assert.equal(showIf('voxel.peel_step'), false, 'no peeling field in plain GCFA');
  model.set('voxel.strategy', 'sp-gcfa');
  assert.equal(showIf('voxel.shadow'), true);
  model.set('voxel.width_mm', 1.2);
  const s = model.toSliceSettings();
  assert.equal(s.method, 'voxel');
  assert.equal(s['voxel.strategy'], 'sp-gcfa');
  assert.equal(s['voxel.width_mm'], 1.2);
  assert.equal('voxel.epsilon' in s, false, 'defaults are not sent');
  model.set('method', 'planar');
  assert.deepEqual(Object.keys(model.toSliceSettings()).filter((k) => k.startsWith('voxel.') || k === 'method'), [],
    'voxel settings are not sent for a planar slice');
  assert.throws(() => model.set('voxel.peel_step', 0), /peel step/);
  assert.throws(() => model.set('voxel.strategy', 'nope'), /unknown choice/);
});
