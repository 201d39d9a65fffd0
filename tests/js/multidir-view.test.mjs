// SPDX-License-Identifier: MIT
// The multidir view's three.js objects (web/methods/multidir-view.js) in Node: parts coloured and drawn in
// print order up to the order slider, an arrow per shown part, the risky faces of the placed
// part before / after as an overlay, toggles, bad buffers failing with the data module's
// message, dispose.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { MultidirView } from '../../web/methods/multidir-view.js';
import { partColor } from '../../web/methods/multidir-data.js';

// Three parts stacked along +Z (print index = z / 10), two triangles each, and a placed mesh of
// 4 triangles (areas 2, 2, 4.5, 4.5) with risky flags.
function makeInputs() {
  const partPositions = [];
  const partTriangles = [];
  const partIds = [];
  for (const i of [2, 0, 1]) {
    const b = partPositions.length / 3;
    partPositions.push(0, 0, 10 * i, 5, 0, 10 * i, 5, 5, 10 * i, 0, 5, 10 * i);
    partTriangles.push(b, b + 1, b + 2, b, b + 2, b + 3);
    partIds.push(i, i);
  }
  const preview = {
    positions: new Float32Array(0), features: new Uint8Array(0), layers: new Uint32Array(0),
    partPositions: new Float32Array(partPositions), partTriangles: new Uint32Array(partTriangles), partIds: new Uint32Array(partIds),
    riskyBefore: new Uint8Array([1, 1, 1, 0]), riskyAfter: new Uint8Array([0, 0, 1, 0]),
  };
  const mesh = {
    positions: new Float32Array([0, 0, 0, 2, 0, 0, 2, 2, 0, 0, 2, 0, 0, 0, 1, 3, 0, 1, 3, 3, 1, 0, 3, 1]),
    indices: new Uint32Array([0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7]),
  };
  const report = {
    part_count: 3,
    parts: [0, 1, 2].map((i) => ({ print_index: i, direction: i === 0 ? [0, 0, 1] : [0, i === 1 ? 1 : -1, 1] })),
  };
  return { preview, mesh, report };
}

test('MultidirView: parts in print order up to the slider, colours per part, arrows', () => {
  const { preview, mesh, report } = makeInputs();
  const v = new MultidirView(preview, report, mesh);
  let s = v.stats();
  assert.equal(s.parts, 3);
  assert.equal(s.order, 2, 'every part at first');
  assert.equal(s.trianglesDrawn, 6);
  assert.equal(s.arrowsDrawn, 3);
  // Sorted by print index: the first two triangles are part 0 (z = 0) in part 0's colour.
  const pos = v.partMesh.geometry.getAttribute('position').array;
  const col = v.partMesh.geometry.getAttribute('color').array;
  for (let k = 0; k < 6; k++) assert.equal(pos[3 * k + 2], 0);
  for (let k = 12; k < 18; k++) assert.equal(pos[3 * k + 2], 20);
  assert.deepEqual([...col.slice(0, 3)], partColor(0));
  assert.deepEqual([...col.slice(36, 39)], partColor(2));
  // The arrow of part 1 starts at its centroid and points along its (normalised) direction.
  const a = v.arrows.geometry.getAttribute('position').array;
  assert.deepEqual([...a.slice(18, 21)].map((x) => Number(x.toFixed(4))), [2.5, 2.5, 10]);
  const dir = [a[21] - a[18], a[22] - a[19], a[23] - a[20]];
  const len = Math.hypot(...dir);
  assert.ok(Math.abs(len - v.arrowLength) < 1e-4);
  assert.ok(Math.abs(dir[0]) < 1e-5 && Math.abs(dir[1] / len - Math.SQRT1_2) < 1e-5 && Math.abs(dir[2] / len - Math.SQRT1_2) < 1e-5);

  assert.equal(v.setOrder(0), 0);
  s = v.stats();
  assert.deepEqual([s.partsShown, s.trianglesDrawn, s.arrowsDrawn], [1, 2, 1]);
  assert.equal(v.arrows.geometry.drawRange.count, 6, 'one arrow: 3 segments');
  assert.equal(v.setOrder(1), 1);
  assert.equal(v.stats().trianglesDrawn, 4);
  assert.equal(v.setOrder(99), 2, 'clamped');
  v.setVisible('arrows', false);
  assert.equal(v.stats().arrowsDrawn, 0);
  v.setVisible('parts', false);
  assert.equal(v.stats().trianglesDrawn, 0);
  assert.throws(() => v.setVisible('tree', true), /no layer 'tree'/);
});

test('MultidirView: risky faces before / after on the placed part', () => {
  const { preview, mesh, report } = makeInputs();
  const v = new MultidirView(preview, report, mesh);
  let s = v.stats();
  assert.equal(s.risky, 'none');
  assert.equal(s.riskyDrawn, 0);
  assert.deepEqual(s.riskyTriangles, { before: 3, after: 1 });
  assert.deepEqual(s.riskyAreaMm2, { before: 2 + 2 + 4.5, after: 4.5 });
  v.setRisky('before');
  s = v.stats();
  assert.equal(s.riskyDrawn, 3);
  assert.ok(v.riskyMeshes.before.visible && !v.riskyMeshes.after.visible);
  assert.deepEqual([...v.riskyMeshes.before.geometry.index.array], [0, 1, 2, 0, 2, 3, 4, 5, 6]);
  v.setRisky('after');
  assert.equal(v.stats().riskyDrawn, 1);
  assert.ok(!v.riskyMeshes.before.visible && v.riskyMeshes.after.visible);
  assert.throws(() => v.setRisky('sometimes'), /risky 'sometimes'/);
  v.setRisky('none');
  assert.ok(!v.riskyMeshes.before.visible && !v.riskyMeshes.after.visible);
});

test('MultidirView: bad buffers fail with the data module\'s message; dispose frees geometry', () => {
  const { preview, mesh, report } = makeInputs();
  assert.throws(() => new MultidirView({ ...preview, partIds: new Uint32Array(2) }, report, mesh), /2 part ids for 6 triangles/);
  assert.throws(() => new MultidirView(preview, report, { ...mesh, indices: new Uint32Array(3) }), /4 risky flags for a mesh of 1 triangles/);
  const v = new MultidirView(preview, report, mesh);
  let disposed = 0;
  v.object.traverse((o) => { if (o.geometry) o.geometry.addEventListener('dispose', () => { disposed += 1; }); });
  v.dispose();
  assert.equal(disposed, 4, 'parts, arrows, risky before, risky after');
  // Without a mesh the risky overlays are empty.
  const w = new MultidirView(preview, report, null);
  w.setRisky('before');
  assert.equal(w.stats().riskyDrawn, 0);
});
