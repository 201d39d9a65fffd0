// SPDX-License-Identifier: MIT
// Pure data preparation for the geodesic method's view (paper 002; no three.js, no DOM;
// unit-tested in Node):
//   - the checked geodesic preview buffers (core/pipeline/preview.h, flattened by wasm/helpers.cpp: the boundary
//     surface with the geodesic distance per vertex, the skeleton tree's nodes and edges, the
//     print sequence), with clear errors when they disagree;
//   - the distance field as vertex colours (a ramp whose lightness grows with the distance) and
//     the surface's triangles sorted by their largest distance, so "the part up to layer l's
//     iso-value" is one draw range;
//   - the skeleton tree as points (coloured like their layer's IGDS surface) and line segments;
//   - the air moves of the print sequence: the transitions a -> b where b is not an upper-node of
//     a (core/geodesic/print_order.h: each is a retraction, its length the distance between the
//     two nodes' centroids), so their count and total length are the report's retractions and
//     air_move_mm;
//   - what is drawn for a layer range and a print step (index lists);
//   - the per-layer overhang chart (report.geodesic.overhang_avg_deg and overhang_ratio) as SVG
//     geometry, the traversal table (report.geodesic.traversals) and the summary rows.
import { rgbCss } from '../colors.js';
import { figure, formatMs, niceTicks, plural, withUnit } from '../format.js';
import { axesFreedRows, layerColor } from './voxel-data.js';

/**
 * Progress stages of a geodesic slice, in pipeline order, with their share of the bar (sums to 1):
 * tet mesh, heat-method field, IGDS, skeleton tree and print order (collision model), spiral
 * paths, tool-path in the chosen sequence. Shares from the demo tree's timings (61k tets: the
 * field's factorisation dominates).
 */
export const GEODESIC_STAGE_WEIGHTS = Object.freeze({
  read: 0.01, validate: 0.08, place: 0.01, tetmesh: 0.16, field: 0.36, igds: 0.17, order: 0.01, collision: 0.04,
  paths: 0.05, toolpath: 0.03, motion: 0.05, program: 0.03,
});

/**
 * Stops of the distance ramp (0..255 RGB, platform first): dark violet, blue, teal, green, yellow.
 * Their luma (0.299 r + 0.587 g + 0.114 b) strictly increases, and luma is linear in RGB, so the
 * piecewise-linear ramp is monotone in lightness: farther is always lighter.
 */
export const FIELD_RAMP = [[0x44, 0x01, 0x54], [0x3b, 0x52, 0x8b], [0x21, 0x91, 0x8c], [0x5e, 0xc9, 0x62], [0xfd, 0xe7, 0x25]];

/** Luma (0..255) of an RGB colour, for tests and legends. */
export function luma([r, g, b]) {
  return 0.299 * r + 0.587 * g + 0.114 * b;
}

/** Colour of t in [0, 1] on the distance ramp (clamped; NaN -> the first stop), 0..255 RGB. */
export function rampColor(t) {
  const x = Number.isFinite(t) ? Math.min(Math.max(t, 0), 1) : 0;
  const s = x * (FIELD_RAMP.length - 1);
  const k = Math.min(Math.floor(s), FIELD_RAMP.length - 2);
  const f = s - k;
  const a = FIELD_RAMP[k];
  const b = FIELD_RAMP[k + 1];
  return [0, 1, 2].map((c) => Math.round(a[c] + f * (b[c] - a[c])));
}

/** CSS linear-gradient of the ramp (left: distance 0). */
export function rampCss() {
  return `linear-gradient(to right, ${FIELD_RAMP.map(rgbCss).join(', ')})`;
}

/** The geodesic preview buffers' names and their element types. */
const BUFFERS = {
  fieldPositions: Float32Array, fieldTriangles: Uint32Array, fieldValues: Float32Array,
  nodePositions: Float32Array, nodeLayers: Uint32Array, treeEdges: Uint32Array, sequence: Uint32Array,
};

/** True when the preview carries the geodesic method's buffers (a field or a skeleton tree). */
export function hasGeodesicBuffers(preview) {
  return !!(preview && ((preview.fieldValues && preview.fieldValues.length > 0)
    || (preview.nodeLayers && preview.nodeLayers.length > 0)));
}

/**
 * Check the geodesic preview buffers against each other: fieldPositions #F*3, fieldTriangles
 * #FT*3 (indices < #F), fieldValues #F finite; nodePositions #N*3 finite, nodeLayers #N,
 * treeEdges #E*2 (indices < #N, from a node to a node one layer up), sequence: every node once.
 * Missing buffers count as empty.
 * @returns {{fieldVertices: number, fieldTriangles: number, nodes: number, edges: number,
 *   layerCount: number, rank: Uint32Array}} layerCount: highest node layer + 1; rank[n]: the
 *   position of node n in the sequence
 * @throws Error naming the first disagreement
 */
export function checkGeodesicBuffers(p) {
  const get = (name) => {
    const a = p ? p[name] : undefined;
    if (a === undefined || a === null) return new BUFFERS[name](0);
    if (!(a instanceof BUFFERS[name])) throw new Error(`geodesic buffers: ${name} is not a ${BUFFERS[name].name}`);
    return a;
  };
  const P = get('fieldPositions');
  const T = get('fieldTriangles');
  const values = get('fieldValues');
  const nodeP = get('nodePositions');
  const layers = get('nodeLayers');
  const edges = get('treeEdges');
  const sequence = get('sequence');
  if (P.length % 3 !== 0) throw new Error(`geodesic buffers: fieldPositions has ${P.length} numbers, not 3 per vertex`);
  const F = P.length / 3;
  if (values.length !== F) throw new Error(`geodesic buffers: ${values.length} field values for ${F} field vertices`);
  if (T.length % 3 !== 0) throw new Error(`geodesic buffers: fieldTriangles has ${T.length} indices, not 3 per triangle`);
  for (let k = 0; k < T.length; k++) {
    if (T[k] >= F) throw new Error(`geodesic buffers: field triangle ${Math.floor(k / 3)} refers to vertex ${T[k]} of ${F}`);
  }
  for (let v = 0; v < F; v++) {
    if (!Number.isFinite(values[v])) throw new Error(`geodesic buffers: field value ${v} is ${values[v]}`);
  }
  const N = layers.length;
  if (nodeP.length !== 3 * N) throw new Error(`geodesic buffers: ${nodeP.length / 3} node positions for ${N} node layers`);
  for (let k = 0; k < nodeP.length; k++) {
    if (!Number.isFinite(nodeP[k])) throw new Error(`geodesic buffers: node ${Math.floor(k / 3)} has a non-finite position`);
  }
  if (edges.length % 2 !== 0) throw new Error(`geodesic buffers: treeEdges has ${edges.length} indices, not 2 per edge`);
  for (let e = 0; e < edges.length; e += 2) {
    const [a, b] = [edges[e], edges[e + 1]];
    if (a >= N || b >= N) throw new Error(`geodesic buffers: tree edge ${e / 2} (${a}, ${b}) refers to a node beyond the ${N} given`);
    if (layers[b] !== layers[a] + 1) {
      throw new Error(`geodesic buffers: tree edge ${e / 2} links layer ${layers[a]} to layer ${layers[b]} (lower to upper expected)`);
    }
  }
  if (sequence.length !== N) throw new Error(`geodesic buffers: the sequence has ${sequence.length} entries for ${N} nodes`);
  const rank = new Uint32Array(N).fill(0xffffffff);
  for (let k = 0; k < N; k++) {
    const n = sequence[k];
    if (n >= N) throw new Error(`geodesic buffers: sequence entry ${k} is node ${n} of ${N}`);
    if (rank[n] !== 0xffffffff) throw new Error(`geodesic buffers: node ${n} appears twice in the sequence (entries ${rank[n]} and ${k})`);
    rank[n] = k;
  }
  let layerCount = 0;
  for (let n = 0; n < N; n++) layerCount = Math.max(layerCount, layers[n] + 1);
  return { fieldVertices: F, fieldTriangles: T.length / 3, nodes: N, edges: edges.length / 2, layerCount, rank };
}

/**
 * Vertex colours of the field (#F*3, 0..255): value v -> rampColor((v - min) / (max - min));
 * min and max default to the values' range.
 * @returns {{colors: Uint8Array, min: number, max: number}}
 */
export function fieldColors(values, { min, max } = {}) {
  let lo = Number.isFinite(min) ? min : Infinity;
  let hi = Number.isFinite(max) ? max : -Infinity;
  if (!Number.isFinite(min) || !Number.isFinite(max)) {
    for (const v of values) {
      if (!Number.isFinite(min) && v < lo) lo = v;
      if (!Number.isFinite(max) && v > hi) hi = v;
    }
  }
  if (!(lo <= hi)) lo = hi = 0;
  const span = hi - lo;
  const colors = new Uint8Array(values.length * 3);
  // A 256-entry table: the ramp is drawn at 8 bits anyway.
  const table = new Uint8Array(256 * 3);
  for (let k = 0; k < 256; k++) table.set(rampColor(k / 255), 3 * k);
  for (let v = 0; v < values.length; v++) {
    const t = span > 0 ? (values[v] - lo) / span : 0;
    const k = Math.round(Math.min(Math.max(t, 0), 1) * 255);
    colors[3 * v] = table[3 * k];
    colors[3 * v + 1] = table[3 * k + 1];
    colors[3 * v + 2] = table[3 * k + 2];
  }
  return { colors, min: lo, max: hi };
}

/**
 * The field surface's triangles sorted by their largest corner value (stable), so the triangles
 * wholly at distance <= d are a prefix (fieldTrianglesUpTo).
 * @returns {{index: Uint32Array, maxValues: Float32Array}} index: 3 per triangle, sorted;
 *   maxValues: each sorted triangle's largest value, non-decreasing
 */
export function sortFieldTriangles(triangles, values) {
  const T = triangles.length / 3;
  const top = new Float32Array(T);
  for (let t = 0; t < T; t++) {
    top[t] = Math.max(values[triangles[3 * t]], values[triangles[3 * t + 1]], values[triangles[3 * t + 2]]);
  }
  const order = Array.from({ length: T }, (_, t) => t).sort((a, b) => top[a] - top[b] || a - b);
  const index = new Uint32Array(3 * T);
  const maxValues = new Float32Array(T);
  order.forEach((t, k) => {
    index[3 * k] = triangles[3 * t];
    index[3 * k + 1] = triangles[3 * t + 1];
    index[3 * k + 2] = triangles[3 * t + 2];
    maxValues[k] = top[t];
  });
  return { index, maxValues };
}

/** How many of the sorted triangles lie wholly at distance <= d (binary search; +inf: all). */
export function fieldTrianglesUpTo(maxValues, d) {
  if (!(d >= maxValues[0])) return d === Infinity ? maxValues.length : 0;
  let lo = 0;
  let hi = maxValues.length;
  while (lo < hi) {
    const mid = (lo + hi) >> 1;
    if (maxValues[mid] <= d) lo = mid + 1;
    else hi = mid;
  }
  return lo;
}

/**
 * Node colours (#N*3, 0..255): layerColor of the node's layer among layerCount (the IGDS
 * surfaces' colours, web/voxel-data.js).
 */
export function nodeColors(nodeLayers, layerCount) {
  const out = new Uint8Array(nodeLayers.length * 3);
  for (let n = 0; n < nodeLayers.length; n++) out.set(layerColor(nodeLayers[n], layerCount), 3 * n);
  return out;
}

/** Segment end points (6 per pair) between the nodes of each index pair (e.g. treeEdges). */
export function pairSegments(nodePositions, pairs) {
  const out = new Float32Array(pairs.length * 3);
  for (let k = 0; k < pairs.length; k++) {
    const n = pairs[k];
    out[3 * k] = nodePositions[3 * n];
    out[3 * k + 1] = nodePositions[3 * n + 1];
    out[3 * k + 2] = nodePositions[3 * n + 2];
  }
  return out;
}

/**
 * The air moves of a print sequence: each transition sequence[k-1] -> sequence[k] whose end is
 * not an upper-node of its start (no tree edge start -> end), as in core/geodesic/print_order.h,
 * where every such transition is a retraction and its air move the distance between the centroids.
 * @returns {{count: number, lengthMm: number, pairs: Uint32Array, steps: Uint32Array,
 *   lengths: Float64Array}} pairs: (from, to) node indices per move; steps: k, the sequence
 *   position of each move's end
 */
export function airMoves(nodePositions, treeEdges, sequence) {
  const upper = new Set();
  const N = nodePositions.length / 3;
  for (let e = 0; e < treeEdges.length; e += 2) upper.add(treeEdges[e] * N + treeEdges[e + 1]);
  const pairs = [];
  const steps = [];
  const lengths = [];
  let total = 0;
  for (let k = 1; k < sequence.length; k++) {
    const a = sequence[k - 1];
    const b = sequence[k];
    if (upper.has(a * N + b)) continue;
    const dx = nodePositions[3 * b] - nodePositions[3 * a];
    const dy = nodePositions[3 * b + 1] - nodePositions[3 * a + 1];
    const dz = nodePositions[3 * b + 2] - nodePositions[3 * a + 2];
    const d = Math.sqrt(dx * dx + dy * dy + dz * dz);
    pairs.push(a, b);
    steps.push(k);
    lengths.push(d);
    total += d;
  }
  return { count: steps.length, lengthMm: total, pairs: Uint32Array.from(pairs), steps: Uint32Array.from(steps), lengths: Float64Array.from(lengths) };
}

/**
 * What the tree view draws for the layer range lo..hi and the print step (sequence positions
 * 0..step printed; step >= N - 1: all): the nodes inside both, the tree edges and air moves
 * whose two nodes are drawn. Index lists (ascending).
 * @returns {{nodes: Uint32Array, edges: Uint32Array, moves: Uint32Array, current: number}}
 *   edges, moves: indices of the pairs (edge e = treeEdges[2e..2e+1]); current: the node printed
 *   at `step` (-1 without nodes)
 */
export function selectTree({ nodeLayers, rank, treeEdges, movePairs }, { lo = 0, hi = Infinity, step = Infinity } = {}) {
  const N = nodeLayers.length;
  const shown = new Uint8Array(N);
  const nodes = [];
  let current = -1;
  for (let n = 0; n < N; n++) {
    if (nodeLayers[n] >= lo && nodeLayers[n] <= hi && rank[n] <= step) {
      shown[n] = 1;
      nodes.push(n);
    }
    if (rank[n] === Math.min(step, N - 1)) current = n;
  }
  const pick = (pairs) => {
    const out = [];
    for (let k = 0; k + 1 < pairs.length; k += 2) if (shown[pairs[k]] && shown[pairs[k + 1]]) out.push(k / 2);
    return Uint32Array.from(out);
  };
  return { nodes: Uint32Array.from(nodes), edges: pick(treeEdges), moves: pick(movePairs || new Uint32Array(0)), current };
}

/**
 * Geometry of the overhang chart in a width x height box (SVG units, y down): x = layer index
 * (layer 0 at the left), left axis the average overhang angle of each layer's IGDS (degrees,
 * 0..max(90, data)), and the overhang ratio (0..1) as bars on the same plot height. Layers whose
 * value is missing or not finite break the line.
 * @param {{layers?: number, overhang_avg_deg: number[], overhang_ratio?: number[]}} g report.geodesic
 * @returns {{layers: number, plot, points: {layer, x, y, value}[], path: string,
 *   bars: {layer, x, y, width, height, value}[], threshold: {value, y}, yTicks: {value, y}[],
 *   xTicks: {value, x}[], maxValue: number, meanValue: number, layerX: (l) => number}}
 *   points, bars: one per layer with a finite value (points.length + missing = layers)
 * @throws Error when the arrays are missing or their lengths disagree with each other or with
 *   g.layers
 */
export function overhangChartGeometry(g, {
  width = 260, height = 120, padLeft = 26, padRight = 6, padTop = 6, padBottom = 18, thresholdDeg = 45,
} = {}) {
  if (!g || typeof g !== 'object') throw new Error('overhang chart: no geodesic report');
  const avg = g.overhang_avg_deg;
  if (!Array.isArray(avg)) throw new Error('overhang chart: overhang_avg_deg is not an array');
  const ratio = g.overhang_ratio === undefined ? null : g.overhang_ratio;
  if (ratio !== null && (!Array.isArray(ratio) || ratio.length !== avg.length)) {
    throw new Error(`overhang chart: ${Array.isArray(ratio) ? ratio.length : 'no'} overhang ratios for ${avg.length} layers`);
  }
  if (Number.isFinite(g.layers) && g.layers !== avg.length) {
    throw new Error(`overhang chart: ${avg.length} overhang angles for ${g.layers} layers`);
  }
  const L = avg.length;
  const plot = { x: padLeft, y: padTop, width: Math.max(width - padLeft - padRight, 1), height: Math.max(height - padTop - padBottom, 1) };
  const num = (x) => (x === null || x === '' || typeof x === 'boolean' ? NaN : Number(x));
  let maxValue = 0;
  let sum = 0;
  let n = 0;
  for (const x of avg) {
    const v = num(x);
    if (!Number.isFinite(v)) continue;
    maxValue = Math.max(maxValue, v);
    sum += v;
    n++;
  }
  const top = Math.max(90, maxValue);
  const layerX = (l) => plot.x + (L > 1 ? (l / (L - 1)) * plot.width : plot.width / 2);
  const y = (deg) => plot.y + plot.height - (deg / top) * plot.height;
  const points = [];
  let path = '';
  let pen = false;
  for (let l = 0; l < L; l++) {
    const v = num(avg[l]);
    if (!Number.isFinite(v)) {
      pen = false;
      continue;
    }
    const p = { layer: l, x: layerX(l), y: y(v), value: v };
    points.push(p);
    path += `${path ? ' ' : ''}${pen ? 'L' : 'M'}${p.x.toFixed(2)} ${p.y.toFixed(2)}`;
    pen = true;
  }
  const bars = [];
  if (ratio) {
    const w = L > 0 ? plot.width / Math.max(L, 1) : 0;
    for (let l = 0; l < L; l++) {
      const r = num(ratio[l]);
      if (!Number.isFinite(r)) continue;
      const h = Math.min(Math.max(r, 0), 1) * plot.height;
      bars.push({ layer: l, x: layerX(l) - w / 2, y: plot.y + plot.height - h, width: w, height: h, value: r });
    }
  }
  const yTicks = [0, 30, 60, 90].filter((v) => v <= top).map((v) => ({ value: v, y: y(v) }));
  const xTicks = L > 0 ? niceTicks(0, L - 1, 4).filter((v) => Number.isInteger(v)).map((v) => ({ value: v, x: layerX(v) })) : [];
  return {
    layers: L, plot, points, path, bars, threshold: { value: thresholdDeg, y: y(thresholdDeg) }, yTicks, xTicks,
    maxValue, meanValue: n ? sum / n : NaN, layerX,
  };
}

/** Traversal names in the order the core reports them. */
export const TRAVERSALS = ['LPT', 'DPT', 'A3'];

/**
 * Rows of the traversal table from report.geodesic.traversals: {name, retractions, airMoveMm,
 * collisionFree, collidingNodes, collidingLowerBound (no order collides on fewer nodes), chosen
 * (the sequence the program follows), fewestRetractions,
 * shortestAir (among the collision-free ones; all when none is)}. Absent traversals are left out.
 */
export function traversalRows(g) {
  const t = g && g.traversals && typeof g.traversals === 'object' ? g.traversals : {};
  const chosen = g && typeof g.sequence === 'string' ? g.sequence.toUpperCase() : '';
  const rows = TRAVERSALS.filter((name) => t[name] && typeof t[name] === 'object').map((name) => ({
    name,
    retractions: Number.isFinite(t[name].retractions) ? t[name].retractions : NaN,
    airMoveMm: Number.isFinite(t[name].air_move_mm) ? t[name].air_move_mm : NaN,
    collisionFree: t[name].collision_free === true,
    collidingNodes: Number.isFinite(t[name].colliding_nodes) ? t[name].colliding_nodes : NaN,
    collidingLowerBound: Number.isFinite(t[name].colliding_lower_bound) ? t[name].colliding_lower_bound : NaN,
    chosen: name === chosen,
  }));
  const pool = rows.some((r) => r.collisionFree) ? rows.filter((r) => r.collisionFree) : rows;
  const least = (key) => Math.min(...pool.map((r) => r[key]).filter(Number.isFinite));
  const fewest = least('retractions');
  const shortest = least('airMoveMm');
  for (const r of rows) {
    r.fewestRetractions = pool.includes(r) && r.retractions === fewest;
    r.shortestAir = pool.includes(r) && r.airMoveMm === shortest;
  }
  return rows;
}

/**
 * Summary rows [key, label, text] of report.geodesic (keys double as data-testid suffixes:
 * geo-<key>), in display order; absent figures show '—'.
 */
export function geodesicSummaryRows(g) {
  const r = g && typeof g === 'object' ? g : {};
  const tree = r.tree && typeof r.tree === 'object' ? r.tree : {};
  const th = r.thickness && typeof r.thickness === 'object' ? r.thickness : {};
  const t = r.timings_ms && typeof r.timings_ms === 'object' ? r.timings_ms : {};
  const yes = (x) => (x === true ? 'yes' : x === false ? 'no' : '—');
  return [
    ['tets', r.tet_source === 'input' ? 'tets (from the file)' : 'tets', figure(r.tets)],
    ['max_geodesic', 'max geodesic distance', withUnit(r.max_geodesic_mm, 'mm')],
    // Steps shorter than the interval where the field is slow at the surface (the core's
    // geodesic.max_thickness_ratio): the range of steps, so a layer count above max / interval reads.
    ['interval', 'IGDS interval', Number.isFinite(r.step_min_mm) && Number.isFinite(r.interval_mm) && r.step_min_mm < r.interval_mm * (1 - 1e-9)
      ? `${withUnit(r.interval_mm, 'mm')} (steps ${figure(r.step_min_mm)}–${figure(r.interval_mm)} mm)`
      : withUnit(r.interval_mm, 'mm')],
    ['layers', 'layers', figure(r.layers)],
    ['igds', 'IGDS (tree nodes)', figure(r.igds)],
    ['tree', 'tree', Number.isFinite(tree.edges)
      ? `${plural(tree.edges, 'edge')}, ${plural(tree.branch_points, 'fork')}${tree.merges ? `, ${plural(tree.merges, 'merge')}` : ''}${tree.is_tree === false ? ' (a graph)' : ''}`
      : '—'],
    ['sequence', 'print sequence', typeof r.sequence === 'string' ? r.sequence : '—'],
    ['retractions', 'retractions', figure(r.retractions)],
    ['air_move', 'air moves', withUnit(r.air_move_mm, 'mm')],
    ['collision_free', 'collision-free', yes(r.collision_free)],
    ['nozzle_angle', 'nozzle angle', Number.isFinite(r.nozzle_angle_deg) ? `${figure(r.nozzle_angle_deg)}°` : '—'],
    ['overhang_avg', 'mean overhang', Number.isFinite(r.overhang_avg_all_deg) ? `${figure(r.overhang_avg_all_deg)}°` : '—'],
    ['overhang_max', 'largest layer overhang', Number.isFinite(r.overhang_max_layer_deg) ? `${figure(r.overhang_max_layer_deg)}°` : '—'],
    ['thickness_dev', 'max thickness deviation', Number.isFinite(th.max_deviation_all_percent) ? `${figure(th.max_deviation_all_percent)} %` : '—'],
    ['paths', 'spiral paths', figure(r.paths)],
    ...axesFreedRows(r),
    ...(r.unfilled_regions ? [['unfilled', 'unfilled IGDS', figure(r.unfilled_regions)]] : []),
    // Tool path left out where no nozzle axis clears the part (drawn red in the view).
    ...(r.skipped_segments > 0 ? [['skipped', 'path left out', `${withUnit(r.skipped_mm, 'mm')} (${plural(r.skipped_segments, 'segment')})${
      Array.isArray(r.skipped_layers) && r.skipped_layers.length === 2 ? `, layers ${r.skipped_layers[0] + 1}–${r.skipped_layers[1] + 1}` : ''}`]] : []),
    ...['tetmesh', 'field', 'igds', 'tree', 'collision', 'paths', 'toolpath']
      .filter((k) => t[k] !== undefined).map((k) => [`time_${k}`, `time: ${k}`, formatMs(t[k])]),
  ];
}

/** One line for the progress text after a geodesic slice. */
export function geodesicDoneSummary(g) {
  if (!g || typeof g !== 'object') return '';
  const free = g.collision_free === true ? 'collision-free' : g.collision_free === false ? 'with collisions' : '';
  return `${figure(g.tets)} tets → ${figure(g.layers)} layers, ${figure(g.igds)} IGDS; ${g.sequence || '?'}: `
    + `${figure(g.retractions)} retractions, ${figure(g.air_move_mm)} mm air${free ? `, ${free}` : ''}`;
}
