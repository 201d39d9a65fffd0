// SPDX-License-Identifier: MIT
// The geodesic view's data preparation (web/methods/geodesic-data.js) against direct computations: the
// distance ramp (end colours, lightness growing with the distance), field colours, triangles
// sorted by their largest distance (every prefix is exactly the triangles within a distance),
// the buffer checks (one error per kind of disagreement), the air moves of a sequence (the
// transitions that do not go up a tree edge, as core/geodesic/print_order.h counts retractions),
// the tree selection for a layer range and print step, the overhang chart's geometry (one point
// per layer with a value, lengths checked against the layer count), the traversal rows and the
// summary rows. Also the settings schema's geodesic rows.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import {
  FIELD_RAMP, TRAVERSALS, airMoves, checkGeodesicBuffers, fieldColors, fieldTrianglesUpTo, geodesicDoneSummary,
  geodesicSummaryRows, hasGeodesicBuffers, luma, nodeColors, overhangChartGeometry, pairSegments, rampColor, selectTree,
  sortFieldTriangles, traversalRows,
} from '../../web/methods/geodesic-data.js';
import { layerColor } from '../../web/methods/voxel-data.js';
import { SettingsModel, normaliseValue } from '../../web/settings-panel.js';
import { fieldsUnavailable, pageFields } from './page-settings.mjs';

function rng(seed) {
  let x = seed;
  return () => ((x = (x * 1103515245 + 12345) % 2147483648) / 2147483648);
}

// A small skeleton tree: a trunk of 4 layers (nodes 0-3), forking at layer 4 into two branches
// of 3 layers each (left 4, 6, 8; right 5, 7, 9); centroids 1 mm apart in z, branches at x = -5
// and +5. Edges (lower, upper) as the core writes them.
function forkTree() {
  const pos = [];
  const layers = [];
  for (let l = 0; l < 4; l++) {
    pos.push(0, 0, l);
    layers.push(l);
  }
  for (let l = 4; l < 7; l++) {
    pos.push(-5, 0, l, 5, 0, l);
    layers.push(l, l);
  }
  const edges = [0, 1, 1, 2, 2, 3, 3, 4, 3, 5, 4, 6, 6, 8, 5, 7, 7, 9];
  return { nodePositions: new Float32Array(pos), nodeLayers: new Uint32Array(layers), treeEdges: new Uint32Array(edges) };
}

test('distance ramp: ends at its first and last stops, lightness grows with the distance', () => {
  assert.deepEqual(rampColor(0), FIELD_RAMP[0]);
  assert.deepEqual(rampColor(1), FIELD_RAMP[FIELD_RAMP.length - 1]);
  assert.deepEqual(rampColor(-3), FIELD_RAMP[0], 'clamped below');
  assert.deepEqual(rampColor(7), FIELD_RAMP[FIELD_RAMP.length - 1], 'clamped above');
  assert.deepEqual(rampColor(NaN), FIELD_RAMP[0]);
  for (let k = 1; k < FIELD_RAMP.length; k++) assert.ok(luma(FIELD_RAMP[k]) > luma(FIELD_RAMP[k - 1]), `stop ${k} lighter`);
  let last = -1;
  for (let i = 0; i <= 1000; i++) {
    const c = rampColor(i / 1000);
    for (const x of c) assert.ok(Number.isInteger(x) && x >= 0 && x <= 255);
    // Rounding to bytes may keep the luma within half a level of the previous sample.
    assert.ok(luma(c) >= last - 0.5, `t = ${i / 1000}: luma ${luma(c)} after ${last}`);
    last = Math.max(last, luma(c));
  }
  assert.ok(luma(rampColor(1)) - luma(rampColor(0)) > 150, 'near black to near white in lightness');
});

test('fieldColors: the range maps onto the ramp; a constant field takes its first colour', () => {
  const values = new Float32Array([2, 12, 7, 4.5, 2, 12]);
  const { colors, min, max } = fieldColors(values);
  assert.equal(min, 2);
  assert.equal(max, 12);
  assert.deepEqual([...colors.subarray(0, 3)], FIELD_RAMP[0]);
  assert.deepEqual([...colors.subarray(3, 6)], FIELD_RAMP[FIELD_RAMP.length - 1]);
  assert.deepEqual([...colors.subarray(6, 9)], rampColor(Math.round(0.5 * 255) / 255));
  // Lighter where farther.
  const order = [0, 3, 2, 1];
  for (let k = 1; k < order.length; k++) {
    assert.ok(luma(colors.subarray(3 * order[k], 3 * order[k] + 3)) > luma(colors.subarray(3 * order[k - 1], 3 * order[k - 1] + 3)));
  }
  // A given range clamps values outside it.
  const clamped = fieldColors(values, { min: 5, max: 6 });
  assert.deepEqual([...clamped.colors.subarray(0, 3)], FIELD_RAMP[0]);
  assert.deepEqual([...clamped.colors.subarray(3, 6)], FIELD_RAMP[FIELD_RAMP.length - 1]);
  const flat = fieldColors(new Float32Array([3, 3, 3]));
  assert.deepEqual([...flat.colors], [...FIELD_RAMP[0], ...FIELD_RAMP[0], ...FIELD_RAMP[0]]);
  assert.equal(fieldColors(new Float32Array(0)).colors.length, 0);
});

test('sortFieldTriangles: each prefix is exactly the triangles whose corners are all within a distance', () => {
  const rnd = rng(11);
  const V = 400;
  const T = 3000;
  const values = new Float32Array(V).map(() => Math.round(rnd() * 500) / 10);  // ties on purpose
  const tri = new Uint32Array(3 * T).map(() => Math.floor(rnd() * V));
  const { index, maxValues } = sortFieldTriangles(tri, values);
  assert.equal(index.length, tri.length);
  for (let k = 1; k < T; k++) assert.ok(maxValues[k] >= maxValues[k - 1], 'non-decreasing');
  // The same triangles (as multisets of index triples).
  const key = (a, t) => `${a[3 * t]},${a[3 * t + 1]},${a[3 * t + 2]}`;
  const count = new Map();
  for (let t = 0; t < T; t++) count.set(key(tri, t), (count.get(key(tri, t)) || 0) + 1);
  for (let t = 0; t < T; t++) count.set(key(index, t), count.get(key(index, t)) - 1);
  assert.ok([...count.values()].every((c) => c === 0), 'a permutation of the triangles');
  for (const d of [-1, 0, 3.3, 10, 25, 49.9, 50, Infinity]) {
    let brute = 0;
    for (let t = 0; t < T; t++) if (Math.max(values[tri[3 * t]], values[tri[3 * t + 1]], values[tri[3 * t + 2]]) <= d) brute++;
    const n = fieldTrianglesUpTo(maxValues, d);
    assert.equal(n, brute, `triangles within ${d}`);
    for (let k = 0; k < n; k++) for (let c = 0; c < 3; c++) assert.ok(values[index[3 * k + c]] <= d);
  }
  assert.equal(fieldTrianglesUpTo(new Float32Array(0), 5), 0);
});

test('checkGeodesicBuffers: agreeing buffers pass; each disagreement names itself', () => {
  const t = forkTree();
  const good = {
    fieldPositions: new Float32Array([0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1]), fieldTriangles: new Uint32Array([0, 2, 1, 0, 1, 3]),
    fieldValues: new Float32Array([0, 1, 1, 2]), ...t, sequence: new Uint32Array([0, 1, 2, 3, 4, 6, 8, 5, 7, 9]),
  };
  const c = checkGeodesicBuffers(good);
  assert.equal(c.fieldVertices, 4);
  assert.equal(c.fieldTriangles, 2);
  assert.equal(c.nodes, 10);
  assert.equal(c.edges, 9);
  assert.equal(c.layerCount, 7);
  assert.deepEqual([...c.rank], [0, 1, 2, 3, 4, 7, 5, 8, 6, 9]);
  assert.equal(hasGeodesicBuffers(good), true);
  assert.equal(hasGeodesicBuffers({ positions: new Float32Array(6) }), false);
  assert.equal(hasGeodesicBuffers(null), false);
  const empty = checkGeodesicBuffers({});
  assert.equal(empty.nodes + empty.fieldVertices + empty.layerCount, 0, 'missing buffers are empty');
  const bad = (patch, re) => assert.throws(() => checkGeodesicBuffers({ ...good, ...patch }), re);
  bad({ fieldPositions: new Float32Array(10) }, /fieldPositions has 10 numbers, not 3 per vertex/);
  bad({ fieldValues: new Float32Array(3) }, /3 field values for 4 field vertices/);
  bad({ fieldTriangles: new Uint32Array([0, 1]) }, /fieldTriangles has 2 indices/);
  bad({ fieldTriangles: new Uint32Array([0, 1, 2, 0, 4, 1]) }, /field triangle 1 refers to vertex 4 of 4/);
  bad({ fieldValues: new Float32Array([0, NaN, 1, 2]) }, /field value 1 is NaN/);
  bad({ nodePositions: new Float32Array(27) }, /9 node positions for 10 node layers/);
  bad({ nodePositions: new Float32Array(30).fill(Infinity) }, /node 0 has a non-finite position/);
  bad({ treeEdges: new Uint32Array([0, 1, 2]) }, /treeEdges has 3 indices/);
  bad({ treeEdges: new Uint32Array([0, 1, 9, 10]) }, /tree edge 1 \(9, 10\) refers to a node beyond the 10 given/);
  bad({ treeEdges: new Uint32Array([1, 0]) }, /tree edge 0 links layer 1 to layer 0/);
  bad({ sequence: new Uint32Array([0, 1, 2]) }, /the sequence has 3 entries for 10 nodes/);
  bad({ sequence: new Uint32Array([0, 1, 2, 3, 4, 6, 8, 5, 7, 7]) }, /node 7 appears twice in the sequence \(entries 8 and 9\)/);
  bad({ sequence: new Uint32Array([0, 1, 2, 3, 4, 6, 8, 5, 7, 12]) }, /sequence entry 9 is node 12 of 10/);
  bad({ nodeLayers: [0, 1] }, /nodeLayers is not a Uint32Array/);
});

test('air moves: the transitions that do not go up a tree edge, with their centroid distances', () => {
  const t = forkTree();
  // Branch by branch (depth first): one air move, from the left tip (8) down to the right fork (5).
  const depth = airMoves(t.nodePositions, t.treeEdges, new Uint32Array([0, 1, 2, 3, 4, 6, 8, 5, 7, 9]));
  assert.equal(depth.count, 1);
  assert.deepEqual([...depth.pairs], [8, 5]);
  assert.deepEqual([...depth.steps], [7]);
  assert.ok(Math.abs(depth.lengthMm - Math.hypot(10, 2)) < 1e-6);
  // Layer by layer: every change of branch is one: 4->5, 5->6, 6->7, 7->8, 8->9 (5 moves of the
  // 9 transitions; 3->4 goes up the tree), each sqrt(100 + dz^2) or 10 mm.
  const layer = airMoves(t.nodePositions, t.treeEdges, new Uint32Array([0, 1, 2, 3, 4, 5, 6, 7, 8, 9]));
  assert.equal(layer.count, 5);
  assert.deepEqual([...layer.pairs], [4, 5, 5, 6, 6, 7, 7, 8, 8, 9]);
  assert.ok(Math.abs(layer.lengthMm - (3 * 10 + 2 * Math.hypot(10, 1))) < 1e-5, `${layer.lengthMm}`);
  // Random DAG-like trees and random orders: the count is the number of transitions that are not
  // tree edges (direction matters: going down an edge is an air move too).
  const rnd = rng(3);
  for (let trial = 0; trial < 20; trial++) {
    const N = 30;
    const pos = new Float32Array(3 * N).map(() => rnd() * 40);
    const edges = [];
    for (let n = 1; n < N; n++) edges.push(Math.floor(rnd() * n), n);
    const seq = Array.from({ length: N }, (_, k) => k);
    for (let k = N - 1; k > 0; k--) {
      const j = Math.floor(rnd() * (k + 1));
      [seq[k], seq[j]] = [seq[j], seq[k]];
    }
    const m = airMoves(pos, new Uint32Array(edges), new Uint32Array(seq));
    let expected = 0;
    let length = 0;
    for (let k = 1; k < N; k++) {
      const [a, b] = [seq[k - 1], seq[k]];
      let edge = false;
      for (let e = 0; e < edges.length; e += 2) if (edges[e] === a && edges[e + 1] === b) edge = true;
      if (!edge) {
        expected++;
        length += Math.hypot(pos[3 * b] - pos[3 * a], pos[3 * b + 1] - pos[3 * a + 1], pos[3 * b + 2] - pos[3 * a + 2]);
      }
    }
    assert.equal(m.count, expected);
    assert.ok(Math.abs(m.lengthMm - length) < 1e-6 * Math.max(1, length));
  }
  assert.equal(airMoves(new Float32Array(0), new Uint32Array(0), new Uint32Array(0)).count, 0);
  // Segments: the end points of each pair, in order.
  const seg = pairSegments(t.nodePositions, depth.pairs);
  assert.deepEqual([...seg], [-5, 0, 6, 5, 0, 4]);
});

test('selectTree: nodes within the layer range and printed by the step; edges and moves between drawn nodes', () => {
  const t = forkTree();
  const sequence = new Uint32Array([0, 1, 2, 3, 4, 6, 8, 5, 7, 9]);
  const { rank } = checkGeodesicBuffers({ ...t, sequence });
  const moves = airMoves(t.nodePositions, t.treeEdges, sequence);
  const all = selectTree({ ...t, rank, movePairs: moves.pairs });
  assert.equal(all.nodes.length, 10);
  assert.equal(all.edges.length, 9);
  assert.equal(all.moves.length, 1);
  assert.equal(all.current, 9, 'the last printed node');
  // Step 6: nodes 0-4, 6, 8 printed; the move 8 -> 5 not yet.
  const s6 = selectTree({ ...t, rank, movePairs: moves.pairs }, { step: 6 });
  assert.deepEqual([...s6.nodes], [0, 1, 2, 3, 4, 6, 8]);
  assert.deepEqual([...s6.edges], [0, 1, 2, 3, 5, 6]);
  assert.equal(s6.moves.length, 0);
  assert.equal(s6.current, 8);
  // Layers 2..4: nodes 2, 3, 4, 5; edges 2-3, 3-4, 3-5.
  const r = selectTree({ ...t, rank, movePairs: moves.pairs }, { lo: 2, hi: 4 });
  assert.deepEqual([...r.nodes], [2, 3, 4, 5]);
  assert.deepEqual([...r.edges], [2, 3, 4]);
  // Brute force over every range and step.
  for (let lo = 0; lo < 7; lo++) {
    for (let hi = lo; hi < 7; hi++) {
      for (let step = 0; step < 10; step++) {
        const s = selectTree({ ...t, rank, movePairs: moves.pairs }, { lo, hi, step });
        const drawn = (n) => t.nodeLayers[n] >= lo && t.nodeLayers[n] <= hi && rank[n] <= step;
        assert.deepEqual([...s.nodes], [...Array(10).keys()].filter(drawn));
        const e = [];
        for (let k = 0; k < 9; k++) if (drawn(t.treeEdges[2 * k]) && drawn(t.treeEdges[2 * k + 1])) e.push(k);
        assert.deepEqual([...s.edges], e);
        assert.equal(s.current, sequence[step]);
      }
    }
  }
  // Node colours are their layer's surface colours.
  const colors = nodeColors(t.nodeLayers, 7);
  for (let n = 0; n < 10; n++) assert.deepEqual([...colors.subarray(3 * n, 3 * n + 3)], layerColor(t.nodeLayers[n], 7));
});

test('overhang chart: one point per layer with a value, on the plot; lengths checked', () => {
  const avg = [10, 12, 20, 35, 50, 48, 30, 0, 15];
  const ratio = [0, 0, 0.1, 0.3, 0.6, 0.5, 0.2, 0, 0.05];
  const c = overhangChartGeometry({ layers: 9, overhang_avg_deg: avg, overhang_ratio: ratio }, { width: 260, height: 120 });
  assert.equal(c.layers, 9);
  assert.equal(c.points.length, 9, 'chart data length equals the layer count');
  assert.equal(c.bars.length, 9);
  const base = c.plot.y + c.plot.height;
  for (let l = 0; l < 9; l++) {
    const p = c.points[l];
    assert.equal(p.layer, l);
    assert.ok(Math.abs(p.y - (base - (avg[l] / 90) * c.plot.height)) < 1e-9, `layer ${l}: y`);
    if (l) assert.ok(p.x > c.points[l - 1].x, 'x grows with the layer');
    assert.ok(Math.abs(c.bars[l].height - ratio[l] * c.plot.height) < 1e-9, `ratio bar ${l}`);
  }
  assert.ok(Math.abs(c.points[0].x - c.plot.x) < 1e-9 && Math.abs(c.points[8].x - (c.plot.x + c.plot.width)) < 1e-9);
  assert.ok(Math.abs(c.threshold.y - (base - 0.5 * c.plot.height)) < 1e-9, '45° halfway up');
  assert.equal(c.maxValue, 50);
  assert.ok(Math.abs(c.meanValue - avg.reduce((a, b) => a + b) / 9) < 1e-12);
  assert.equal((c.path.match(/M/g) || []).length, 1, 'one unbroken line');
  assert.deepEqual(c.yTicks.map((t) => t.value), [0, 30, 60, 90]);
  assert.ok(c.xTicks.length >= 2 && c.xTicks.every((t) => Number.isInteger(t.value) && t.value >= 0 && t.value <= 8));
  // Missing values break the line; an angle above 90° raises the scale.
  const gaps = overhangChartGeometry({ overhang_avg_deg: [5, null, 20, 'x', 30, 100] });
  assert.equal(gaps.points.length, 3 + 1);
  assert.equal((gaps.path.match(/M/g) || []).length, 3);
  assert.equal(gaps.maxValue, 100);
  assert.ok(gaps.points.every((p) => p.y >= gaps.plot.y - 1e-9), 'inside the plot');
  // Disagreements are errors.
  assert.throws(() => overhangChartGeometry({ layers: 10, overhang_avg_deg: avg }), /9 overhang angles for 10 layers/);
  assert.throws(() => overhangChartGeometry({ overhang_avg_deg: avg, overhang_ratio: [1] }), /1 overhang ratios for 9 layers/);
  assert.throws(() => overhangChartGeometry({ overhang_avg_deg: 'a lot' }), /not an array/);
  assert.throws(() => overhangChartGeometry(null), /no geodesic report/);
  const none = overhangChartGeometry({ layers: 0, overhang_avg_deg: [] });
  assert.equal(none.points.length, 0);
  assert.equal(none.path, '');
});

test('traversal rows: the chosen one marked, the best figures among the collision-free', () => {
  const g = {
    sequence: 'A3',
    traversals: {
      LPT: { retractions: 120, air_move_mm: 2300, collision_free: true, colliding_nodes: 0 },
      DPT: { retractions: 2, air_move_mm: 90, collision_free: false, colliding_nodes: 14, colliding_lower_bound: 3 },
      A3: { retractions: 20, air_move_mm: 600, collision_free: true, colliding_nodes: 0 },
    },
  };
  const rows = traversalRows(g);
  assert.equal(rows[1].collidingLowerBound, 3);
  assert.ok(Number.isNaN(rows[0].collidingLowerBound), 'absent: NaN');
  assert.deepEqual(rows.map((r) => r.name), TRAVERSALS);
  assert.deepEqual(rows.map((r) => r.chosen), [false, false, true]);
  assert.deepEqual(rows.map((r) => r.fewestRetractions), [false, false, true], 'DPT collides: not counted');
  assert.deepEqual(rows.map((r) => r.shortestAir), [false, false, true]);
  assert.equal(rows[1].collidingNodes, 14);
  // None collision-free: the best among all.
  const allBad = traversalRows({ sequence: 'lpt', traversals: { LPT: { ...g.traversals.LPT, collision_free: false }, DPT: g.traversals.DPT } });
  assert.deepEqual(allBad.map((r) => [r.name, r.chosen, r.fewestRetractions]), [['LPT', true, false], ['DPT', false, true]]);
  assert.deepEqual(traversalRows({}), []);
  assert.deepEqual(traversalRows(null), []);
});

test('summary rows and the done line show the report\'s figures; absent ones a dash', () => {
  const g = {
    tets: 61234, tet_source: 'mesher', max_geodesic_mm: 51.25, interval_mm: 0.8, layers: 64, igds: 140,
    tree: { nodes: 140, edges: 139, is_tree: true, branch_points: 1, merges: 0 }, sequence: 'A3', retractions: 12,
    air_move_mm: 212.5, collision_free: true, nozzle_angle_deg: 30, overhang_avg_all_deg: 18.2, overhang_max_layer_deg: 41.7,
    thickness: { max_deviation_all_percent: 35.5 }, paths: 300, timings_ms: { tetmesh: 1500, field: 420, igds: 2300.4 },
    axes_freed: 4321, axis_freedom_deg: 15,
  };
  const rows = geodesicSummaryRows(g);
  const byKey = Object.fromEntries(rows.map(([k, , text]) => [k, text]));
  assert.equal(new Set(rows.map((r) => r[0])).size, rows.length, 'keys unique (they become test ids)');
  assert.equal(byKey.tets, '61,234');
  assert.equal(byKey.max_geodesic, '51.25 mm');
  assert.equal(byKey.tree, '139 edges, 1 fork');
  assert.equal(byKey.retractions, '12');
  assert.equal(byKey.air_move, '212.5 mm');
  assert.equal(byKey.collision_free, 'yes');
  assert.equal(byKey.nozzle_angle, '30°');
  assert.equal(byKey.axes_freed, '4,321 (≤ 15°)');
  assert.equal(byKey.thickness_dev, '35.5 %');
  assert.equal(byKey.time_tetmesh, '1.50 s');
  assert.equal(byKey.time_igds, '2.30 s');
  assert.equal(byKey.time_field, '420 ms');
  assert.equal(byKey.interval, '0.8 mm', 'no step range without step_min_mm');
  assert.equal(Object.fromEntries(geodesicSummaryRows({ ...g, step_min_mm: 0.41847 }).map(([k, , text]) => [k, text])).interval,
    '0.8 mm (steps 0.4185–0.8 mm)');
  assert.equal(Object.fromEntries(geodesicSummaryRows({ ...g, step_min_mm: 0.8 }).map(([k, , text]) => [k, text])).interval,
    '0.8 mm', 'uniform steps: the interval alone');
  assert.equal(byKey.skipped, undefined, 'no row when nothing was left out');
  assert.equal(Object.fromEntries(geodesicSummaryRows({ ...g, skipped_segments: 136, skipped_mm: 68.57, skipped_layers: [119, 126] })
    .map(([k, , text]) => [k, text])).skipped, '68.57 mm (136 segments), layers 120–127', 'layers counted from 1 as the slider');
  assert.equal(geodesicDoneSummary(g), '61,234 tets → 64 layers, 140 IGDS; A3: 12 retractions, 212.5 mm air, collision-free');
  const blank = Object.fromEntries(geodesicSummaryRows({}).map(([k, , text]) => [k, text]));
  for (const k of ['tets', 'layers', 'retractions', 'air_move', 'collision_free', 'tree']) assert.equal(blank[k], '—', k);
  assert.equal(geodesicDoneSummary(null), '');
});

test('settings schema: geodesic rows shown and sent only for the geodesic method, defaults as the core\'s', { skip: fieldsUnavailable }, async () => {
  const fields = await pageFields();
  const model = new SettingsModel(fields);
  const field = (key) => fields.find((f) => f.key === key);
  const keys = fields.filter((f) => f.group === 'Geodesic').map((f) => f.key);
  assert.deepEqual(keys, ['geodesic.interval_mm', 'geodesic.tet_size_mm', 'geodesic.target_tets', 'geodesic.base_band_mm',
    'geodesic.max_thickness_ratio', 'geodesic.align_passes', 'geodesic.align_retry_passes', 'geodesic.heat_time',
    'geodesic.nozzle_angle_deg', 'geodesic.sequence', 'geodesic.remesh']);
  assert.ok(field('method').options.some((o) => o.value === 'geodesic'), 'a method choice');
  for (const k of keys) assert.equal(field(k).showIf(model.values), false, `${k} hidden for planar`);
  model.set('geodesic.interval_mm', 0.8);
  model.set('geodesic.sequence', 'lpt');
  assert.equal('geodesic.interval_mm' in model.toSliceSettings(), false, 'not sent for planar');
  model.set('method', 'geodesic');
  for (const k of keys) assert.equal(field(k).showIf(model.values), true, `${k} shown for geodesic`);
  for (const k of ['infill_pattern', 'direction']) assert.equal(field(k).showIf(model.values), false, `${k} hidden for geodesic`);
  for (const k of ['infill', 'walls']) assert.equal(field(k).showIf?.(model.values) ?? true, true, `${k} shown for geodesic (sparse curved layers)`);
  assert.equal(field('layer_height').showIf(model.values), true, 'the interval defaults to the layer height');
  const s = model.toSliceSettings();
  assert.equal(s.method, 'geodesic');
  assert.equal(s['geodesic.interval_mm'], 0.8);
  assert.equal(s['geodesic.sequence'], 'lpt');
  assert.equal('geodesic.nozzle_angle_deg' in s, false, 'defaults are left to the core');
  model.set('geodesic.tet_size_mm', 1.5);
  assert.equal(field('geodesic.target_tets').showIf(model.values), false, 'the target count is unused with a tet size');
  // The core's defaults and ranges (core/pipeline/settings_table.cpp), which the fields take.
  assert.deepEqual(keys.map((k) => field(k).value), [0, 0, 60000, 0, 0.7, 40, 50, 1, 0, 'a3', true]);
  assert.throws(() => normaliseValue(field('geodesic.align_passes'), '101'), /within 0..100/);
  assert.throws(() => normaliseValue(field('geodesic.base_band_mm'), '21'), /within 0..20/);
  assert.throws(() => normaliseValue(field('geodesic.max_thickness_ratio'), '3.5'), /within 0..3/);
  assert.throws(() => normaliseValue(field('geodesic.nozzle_angle_deg'), '90'), /within 0..89/);
  assert.throws(() => normaliseValue(field('geodesic.interval_mm'), '-1'), /within/);
  assert.throws(() => normaliseValue(field('geodesic.target_tets'), '99'), /within/);
  assert.throws(() => normaliseValue(field('geodesic.sequence'), 'bfs'), /unknown choice/);
});
