// SPDX-License-Identifier: MIT
// The geodesic view's three.js objects (web/methods/geodesic-view.js) in Node: the field surface carries
// the ramp colours and draws exactly the triangles within the top layer's iso-value; the tree's
// points, edges and air moves follow the layer range, the print step and the toggles; the air
// moves are the sequence's transitions off the tree; bad buffers fail with the data module's
// message; dispose frees every geometry.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { GeodesicView, SKIPPED_COLOR } from '../../web/methods/geodesic-view.js';
import { FIELD_RAMP } from '../../web/methods/geodesic-data.js';

// A cylinder-like field surface (rings of 12 vertices, z = 0..L-1 mm, value = z) and a fork tree
// over L = 7 layers: trunk nodes 0-3 (layers 0-3), then two branches (4, 6, 8) and (5, 7, 9).
function makePreview(sequence) {
  const L = 7;
  const fieldPositions = [];
  const fieldValues = [];
  const fieldTriangles = [];
  for (let l = 0; l < L; l++) {
    for (let k = 0; k < 12; k++) {
      const a = (k / 12) * 2 * Math.PI;
      fieldPositions.push(5 * Math.cos(a), 5 * Math.sin(a), l);
      fieldValues.push(l);
    }
  }
  for (let l = 0; l + 1 < L; l++) {
    for (let k = 0; k < 12; k++) {
      const a = 12 * l + k;
      const b = 12 * l + ((k + 1) % 12);
      fieldTriangles.push(a, b, b + 12, a, b + 12, a + 12);
    }
  }
  const nodePositions = [];
  const nodeLayers = [];
  for (let l = 0; l < 4; l++) {
    nodePositions.push(0, 0, l);
    nodeLayers.push(l);
  }
  for (let l = 4; l < 7; l++) {
    nodePositions.push(-3, 0, l, 3, 0, l);
    nodeLayers.push(l, l);
  }
  return {
    positions: new Float32Array(0), features: new Uint8Array(0), layers: new Uint32Array(0),
    fieldPositions: new Float32Array(fieldPositions), fieldTriangles: new Uint32Array(fieldTriangles),
    fieldValues: new Float32Array(fieldValues), nodePositions: new Float32Array(nodePositions),
    nodeLayers: new Uint32Array(nodeLayers), treeEdges: new Uint32Array([0, 1, 1, 2, 2, 3, 3, 4, 3, 5, 4, 6, 6, 8, 5, 7, 7, 9]),
    sequence: new Uint32Array(sequence),
  };
}
const REPORT = { layers: 7, iso_values_mm: [0, 1, 2, 3, 4, 5, 6] };
const LAYER_BY_LAYER = [0, 1, 2, 3, 4, 5, 6, 7, 8, 9];

test('GeodesicView: the field up to the top layer\'s iso-value, coloured by distance', () => {
  const v = new GeodesicView(makePreview(LAYER_BY_LAYER), REPORT);
  let s = v.stats();
  assert.equal(s.fieldTriangles, 6 * 24);
  assert.equal(s.fieldDrawn, 6 * 24, 'everything at the last layer');
  assert.equal(s.fieldMin, 0);
  assert.equal(s.fieldMax, 6);
  const colors = v.fieldMesh.geometry.getAttribute('color');
  assert.equal(colors.normalized, true);
  assert.deepEqual([...colors.array.subarray(0, 3)], FIELD_RAMP[0], 'platform ring: first ramp colour');
  assert.deepEqual([...colors.array.subarray(3 * 72, 3 * 72 + 3)], FIELD_RAMP[FIELD_RAMP.length - 1], 'top ring: last');
  for (const hi of [0, 1, 3, 5]) {
    v.setLayerRange(0, hi);
    s = v.stats();
    // The bands between rings j and j + 1 (max value j + 1) are within iso-value hi for j < hi.
    assert.equal(s.fieldDrawn, 24 * hi, `layers 0..${hi}`);
    const index = v.fieldMesh.geometry.index.array;
    const values = makePreview(LAYER_BY_LAYER).fieldValues;
    for (let k = 0; k < 3 * s.fieldDrawn; k++) assert.ok(values[index[k]] <= hi);
  }
  v.setVisible('field', false);
  assert.equal(v.stats().fieldDrawn, 0);
  assert.equal(v.fieldMesh.visible, false);
});

test('GeodesicView: tree points, edges and air moves follow the range, the step and the toggles', () => {
  const v = new GeodesicView(makePreview(LAYER_BY_LAYER), REPORT);
  let s = v.stats();
  assert.equal(s.nodes, 10);
  assert.equal(s.nodesDrawn, 10);
  assert.equal(s.edges, 9);
  assert.equal(s.edgesDrawn, 9);
  // Layer by layer over two branches: 4->5, 5->6, 6->7, 7->8, 8->9.
  assert.equal(s.airMoves, 5);
  assert.equal(s.airDrawn, 5);
  assert.ok(Math.abs(s.airMoveMm - (3 * 6 + 2 * Math.hypot(6, 1))) < 1e-5, `${s.airMoveMm} mm`);
  assert.equal(s.current.node, 9);
  assert.equal(v.currentPoint.visible, false, 'no mark when everything is printed');
  // The index buffers hold what the selection says (vertex pairs of the drawn segments).
  v.setStep(6);
  s = v.stats();
  assert.equal(s.nodesDrawn, 7);
  assert.deepEqual([...v.nodePoints.geometry.index.array.subarray(0, 7)], [0, 1, 2, 3, 4, 5, 6]);
  assert.equal(v.nodePoints.geometry.drawRange.count, 7);
  assert.equal(s.airDrawn, 2, 'moves 4->5 and 5->6 are done by step 6');
  assert.ok(Math.abs(s.airDrawnMm - (6 + Math.hypot(6, 1))) < 1e-5);
  const air = v.airLines.geometry;
  assert.equal(air.drawRange.count, 4);
  const pos = air.getAttribute('position').array;
  const ends = [...air.index.array.subarray(0, 4)].map((i) => [...pos.subarray(3 * i, 3 * i + 3)]);
  assert.deepEqual(ends, [[-3, 0, 4], [3, 0, 4], [3, 0, 4], [-3, 0, 5]]);
  assert.equal(s.current.node, 6);
  assert.equal(v.currentPoint.visible, true);
  assert.deepEqual([...v.currentPosition.array], [-3, 0, 5]);
  v.setLayerRange(4, 6);
  s = v.stats();
  assert.equal(s.nodesDrawn, 3, 'nodes 4, 5, 6');
  assert.equal(s.edgesDrawn, 1, 'edge 4-6');
  v.setStep(99);
  assert.equal(v.stats().step, 9, 'clamped');
  v.setVisible('tree', false);
  v.setVisible('air', false);
  s = v.stats();
  assert.equal(s.nodesDrawn + s.edgesDrawn + s.airDrawn, 0);
  assert.throws(() => v.setVisible('bogus', true), /no layer 'bogus'/);
  // Skipped tool path: the segments of the layer range drawn in their colour, off by the toggle.
  assert.deepEqual([s.skipped, s.skippedDrawn], [0, 0], 'none in this preview');
  assert.equal(v.skippedLines.visible, false);
  const gaps = new GeodesicView({
    ...makePreview(LAYER_BY_LAYER),
    skippedSegments: new Float32Array([0, 0, 5, 1, 0, 5, 1, 0, 6, 2, 0, 6.5]), skippedLayers: new Uint32Array([5, 6]),
  }, REPORT);
  assert.deepEqual([gaps.stats().skipped, gaps.stats().skippedDrawn], [2, 2]);
  gaps.setLayerRange(6, 6);
  assert.deepEqual([gaps.stats().skipped, gaps.stats().skippedDrawn], [2, 1]);
  const drawn = gaps.skippedLines.geometry;
  assert.equal(drawn.drawRange.count, 2);
  assert.deepEqual([...drawn.index.array.subarray(0, 2)].map((i) => [...drawn.getAttribute('position').array.subarray(3 * i, 3 * i + 3)]),
    [[1, 0, 6], [2, 0, 6.5]], 'the layer-6 segment');
  gaps.setLayerRange(0, 4);
  assert.deepEqual([gaps.stats().skippedDrawn, gaps.skippedLines.visible], [0, false]);
  gaps.setLayerRange(0, 6);
  assert.equal(gaps.skippedLines.material.color.getHex(), SKIPPED_COLOR);
  gaps.setVisible('skipped', false);
  assert.deepEqual([gaps.stats().skippedDrawn, gaps.skippedLines.visible], [0, false]);
  assert.throws(() => new GeodesicView({ ...makePreview(LAYER_BY_LAYER), skippedSegments: new Float32Array(6) }, REPORT),
    /0 skipped-segment layers for 1 skipped segments/);
  // Branch by branch: one air move (from the left tip down to the right fork).
  const depth = new GeodesicView(makePreview([0, 1, 2, 3, 4, 6, 8, 5, 7, 9]), REPORT);
  assert.equal(depth.stats().airMoves, 1);
});

test('GeodesicView: bad buffers fail with a clear message; dispose frees the geometries', () => {
  const p = makePreview(LAYER_BY_LAYER);
  assert.throws(() => new GeodesicView({ ...p, sequence: new Uint32Array([0, 1, 2]) }, REPORT), /the sequence has 3 entries for 10 nodes/);
  assert.throws(() => new GeodesicView({ ...p, fieldValues: new Float32Array(5) }, REPORT), /5 field values for 84 field vertices/);
  // No report: the field is drawn whole (no iso-values); an empty preview makes an empty view.
  const bare = new GeodesicView(p);
  assert.equal(bare.stats().fieldDrawn, 144);
  const empty = new GeodesicView({});
  assert.deepEqual([empty.stats().nodes, empty.stats().fieldDrawn, empty.stats().airMoves], [0, 0, 0]);
  let disposed = 0;
  const v = new GeodesicView(p, REPORT);
  v.object.traverse((o) => { if (o.geometry) o.geometry.addEventListener('dispose', () => disposed++); });
  v.dispose();
  assert.equal(disposed, 6, 'field, nodes, edges, air moves, skipped path, current mark');
});
