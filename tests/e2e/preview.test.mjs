// SPDX-License-Identifier: MIT
// The preview's typed-array builder (web/preview.js) against a direct computation: index buffers
// grouped by layer, stable in print order, travel separated, colours from the feature palette,
// and a layer range maps to exactly the segments of those layers.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { buildPreviewArrays, FEATURES, ToolpathPreview } from '../../web/preview.js';
import { CURVE_COLORS } from '../../web/methods/isoplanar-data.js';

// Deterministic pseudo-random preview: layers mostly increasing with some out-of-order segments.
function makePreview(S, L, seed = 7) {
  let x = seed;
  const rnd = () => ((x = (x * 1103515245 + 12345) % 2147483648) / 2147483648);
  const positions = new Float32Array(S * 6).map(() => rnd() * 100);
  const features = new Uint8Array(S).map(() => Math.floor(rnd() * 7));
  const layers = new Uint32Array(S).map((_, s) => (rnd() < 0.1 ? Math.floor(rnd() * L) : Math.floor((s * L) / S)));
  return { positions, features, layers };
}

test('buildPreviewArrays groups segments by layer, stably, print and travel apart', async () => {
  const S = 50_000;
  const L = 97;
  const p = makePreview(S, L);
  // Small blocks and budget force many yields.
  const a = await buildPreviewArrays(p, { block: 1000, budgetMs: 0 });
  assert.equal(a.layerCount, Math.max(...p.layers) + 1);
  for (const [group, keep] of [[a.print, (s) => p.features[s] !== 0], [a.travel, (s) => p.features[s] === 0]]) {
    const expected = [];
    for (let l = 0; l < a.layerCount; l++) {
      assert.equal(group.starts[l], expected.length, `start of layer ${l}`);
      for (let s = 0; s < S; s++) if (keep(s) && p.layers[s] === l) expected.push(s);
    }
    assert.equal(group.starts[a.layerCount], expected.length);
    assert.equal(group.index.length, expected.length * 2);
    for (let k = 0; k < expected.length; k++) {
      assert.equal(group.index[2 * k], 2 * expected[k]);
      assert.equal(group.index[2 * k + 1], 2 * expected[k] + 1);
    }
  }
  for (let s = 0; s < S; s += 997) {
    const c = FEATURES[p.features[s]].color;
    assert.deepEqual([...a.colors.subarray(s * 6, s * 6 + 6)], [...c, ...c]);
  }
  for (const f of FEATURES) assert.equal(a.featureCounts[f.code], p.features.filter((x) => x === f.code).length);
});

test('ToolpathPreview draws exactly the segments of the chosen layer range', async () => {
  const p = makePreview(20_000, 40, 3);
  const preview = await ToolpathPreview.build(p);
  const count = (lo, hi, travel) => p.layers.filter((l, s) => l >= lo && l <= hi && (p.features[s] === 0) === travel).length;
  for (const [lo, hi] of [[0, 39], [0, 0], [10, 20], [39, 39], [25, 5], [-3, 100]]) {
    preview.setLayerRange(lo, hi);
    const [a, b] = preview.range;
    assert.equal(preview.printLines.geometry.drawRange.count / 2, count(a, b, false), `print ${lo}..${hi}`);
    assert.equal(preview.travelLines.geometry.drawRange.count / 2, count(a, b, true), `travel ${lo}..${hi}`);
  }
  assert.deepEqual(preview.range, [0, 39], "out-of-range bounds are clamped");
  await assert.rejects(ToolpathPreview.build({ ...p, layers: p.layers.subarray(1) }), /disagree/);
});

test('segments on iso-planar NL curves alternate between two colours curve by curve', async () => {
  const p = makePreview(6000, 10, 5);
  // Curves numbered in print order: runs of 40 segments, every fifth segment off the curves.
  const curves = new Uint32Array(6000).map((_, s) => (s % 5 === 4 ? 0 : 1 + Math.floor(s / 40)));
  const a = await buildPreviewArrays({ ...p, curves }, { block: 700, budgetMs: 0 });
  let maxCurve = 0;
  for (let s = 0; s < 6000; s++) {
    const onCurve = curves[s] > 0 && p.features[s] !== 0;
    if (onCurve) maxCurve = Math.max(maxCurve, curves[s]);
    const c = onCurve ? CURVE_COLORS[(curves[s] - 1) % 2] : FEATURES[p.features[s]].color;
    assert.deepEqual([...a.colors.subarray(s * 6, s * 6 + 6)], [...c, ...c], `segment ${s}`);
  }
  assert.equal(a.curveCount, maxCurve);
  let minLayer = Infinity;
  for (let s = 0; s < 6000; s++) if (curves[s] > 0 && p.features[s] !== 0) minLayer = Math.min(minLayer, p.layers[s]);
  assert.equal(a.curveLayerMin, minLayer, 'lowest layer with NL curve segments');
  // Adjacent curves differ in colour.
  const colorOf = (k) => {
    const s = (k - 1) * 40 + 1;  // an on-curve segment of curve k (s % 5 != 4) unless it is travel
    for (let t = s; t < s + 4; t++) if (p.features[t] !== 0) return [...a.colors.subarray(t * 6, t * 6 + 3)];
    return null;
  };
  for (let k = 1; k < 100; k++) {
    const [x, y] = [colorOf(k), colorOf(k + 1)];
    if (x && y) assert.notDeepEqual(x, y, `curves ${k} and ${k + 1}`);
  }
  // A curves buffer of the wrong length is ignored (feature colours), none given: curveCount 0.
  const b = await buildPreviewArrays({ ...p, curves: curves.subarray(1) });
  assert.equal(b.curveCount, 0);
  assert.equal(b.curveLayerMin, -1);
  assert.deepEqual([...b.colors.subarray(0, 6)], [...FEATURES[p.features[0]].color, ...FEATURES[p.features[0]].color]);
});
