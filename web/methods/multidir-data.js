// SPDX-License-Identifier: MIT
// Pure data preparation for the multi-directional method's page (paper 000; no three.js, no DOM;
// unit-tested in Node):
//   - the preview buffers checked against each other (partPositions, partTriangles, partIds,
//     riskyBefore, riskyAfter; core/pipeline/preview.h, flattened by wasm/helpers.cpp);
//   - the parts' triangles sorted by print index, so "parts 0..k" is one draw range, with a
//     distinct colour per part;
//   - an arrow per part: its print direction from its surface centroid;
//   - the risky faces of the placed part (before / after) as an index list and their area;
//   - the J_G-per-search-level chart geometry (SVG units), the summary rows and the parts table
//     of report.multidir;
//   - the search-level progress events of a running decomposition (progress.search) as a line of
//     text and as the live chart's values.
import { hslToRgb } from '../colors.js';
import { figure, formatMs, niceTicks, withUnit } from '../format.js';

/**
 * Progress stages of a multidir slice, in pipeline order, with their share of the bar (sums to 1):
 * the plane search (one progress step per search level), clipping into parts, planar slicing and
 * planning of each part along its direction.
 */
export const MULTIDIR_STAGE_WEIGHTS = Object.freeze({
  read: 0.02, validate: 0.05, place: 0.01, decompose: 0.45, clip: 0.05, slice: 0.12, toolpath: 0.18, motion: 0.07, program: 0.05,
});

/** A slice result carries multidir buffers (the parts' meshes). */
export function hasMultidirBuffers(preview) {
  return !!(preview && preview.partIds && preview.partIds.length > 0);
}

/**
 * Check the multidir preview buffers: partPositions #V*3 finite, partTriangles #T*3 (indices
 * < #V), partIds #T; riskyBefore and riskyAfter one flag per triangle of the placed mesh
 * (meshTriangles, when given) and of equal length. Missing buffers count as empty.
 * @returns {{vertices: number, triangles: number, parts: number, meshTriangles: number}} parts:
 *   highest part id + 1
 * @throws Error naming the first disagreement
 */
export function checkMultidirBuffers(preview, meshTriangles = null) {
  const get = (k, T) => (preview && preview[k]) || new T(0);
  const P = get('partPositions', Float32Array);
  const T = get('partTriangles', Uint32Array);
  const ids = get('partIds', Uint32Array);
  const before = get('riskyBefore', Uint8Array);
  const after = get('riskyAfter', Uint8Array);
  if (P.length % 3 !== 0) throw new Error(`multidir buffers: partPositions has ${P.length} numbers, not 3 per vertex`);
  if (T.length % 3 !== 0) throw new Error(`multidir buffers: partTriangles has ${T.length} indices, not 3 per triangle`);
  const V = P.length / 3;
  const nt = T.length / 3;
  if (ids.length !== nt) throw new Error(`multidir buffers: ${ids.length} part ids for ${nt} triangles`);
  for (let k = 0; k < P.length; k++) {
    if (!Number.isFinite(P[k])) throw new Error(`multidir buffers: vertex ${Math.floor(k / 3)} is not finite`);
  }
  for (let k = 0; k < T.length; k++) {
    if (T[k] >= V) throw new Error(`multidir buffers: triangle ${Math.floor(k / 3)} uses vertex ${T[k]} of ${V}`);
  }
  let parts = 0;
  for (const id of ids) parts = Math.max(parts, id + 1);
  if (before.length !== after.length) {
    throw new Error(`multidir buffers: ${before.length} risky-before flags and ${after.length} risky-after flags`);
  }
  if (meshTriangles !== null && before.length !== 0 && before.length !== meshTriangles) {
    throw new Error(`multidir buffers: ${before.length} risky flags for a mesh of ${meshTriangles} triangles`);
  }
  return { vertices: V, triangles: nt, parts, meshTriangles: before.length };
}

/**
 * Colour of part i (0..255 RGB): hues spread by the golden angle so neighbours in print order
 * differ strongly; the platform part (0) is a calm blue.
 */
export function partColor(i) {
  return hslToRgb((215 + 137.508 * i) % 360, 0.62, i % 2 ? 0.58 : 0.5);
}

/** CSS colour of part i. */
export function partColorCss(i) {
  const [r, g, b] = partColor(i);
  return `rgb(${r}, ${g}, ${b})`;
}

/**
 * De-index the parts' soup and sort its triangles by part (stable), with a colour per vertex.
 * @returns {{positions: Float32Array, colors: Uint8Array, starts: Uint32Array, parts: number,
 *   triangles: number}} positions/colors: 9 per triangle; starts[i]: the first triangle of part i
 *   (starts[parts] = triangles), so parts 0..k are triangles 0..starts[k+1]-1
 */
export function sortPartTriangles({ partPositions, partTriangles, partIds }, parts = null) {
  const nt = partIds.length;
  let n = parts;
  if (n === null) {
    n = 0;
    for (const id of partIds) n = Math.max(n, id + 1);
  }
  const starts = new Uint32Array(n + 1);
  for (const id of partIds) starts[id + 1] += 1;
  for (let i = 0; i < n; i++) starts[i + 1] += starts[i];
  const next = starts.slice(0, n);
  const positions = new Float32Array(9 * nt);
  const colors = new Uint8Array(9 * nt);
  const palette = [];
  for (let i = 0; i < n; i++) palette.push(partColor(i));
  for (let t = 0; t < nt; t++) {
    const id = partIds[t];
    const o = next[id]++;
    for (let c = 0; c < 3; c++) {
      const v = partTriangles[3 * t + c];
      for (let k = 0; k < 3; k++) {
        positions[9 * o + 3 * c + k] = partPositions[3 * v + k];
        colors[9 * o + 3 * c + k] = palette[id][k];
      }
    }
  }
  return { positions, colors, starts, parts: n, triangles: nt };
}

/**
 * Area-weighted surface centroid of each part of the soup (NaN for a part without area).
 * @returns {Float64Array} #parts*3
 */
export function partCentroids({ partPositions: P, partTriangles: T, partIds }, parts) {
  const sum = new Float64Array(3 * parts);
  const area = new Float64Array(parts);
  for (let t = 0; t < partIds.length; t++) {
    const a = 3 * T[3 * t], b = 3 * T[3 * t + 1], c = 3 * T[3 * t + 2];
    const ux = P[b] - P[a], uy = P[b + 1] - P[a + 1], uz = P[b + 2] - P[a + 2];
    const vx = P[c] - P[a], vy = P[c + 1] - P[a + 1], vz = P[c + 2] - P[a + 2];
    const w = 0.5 * Math.hypot(uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx);
    const id = partIds[t];
    area[id] += w;
    for (let k = 0; k < 3; k++) sum[3 * id + k] += (w * (P[a + k] + P[b + k] + P[c + k])) / 3;
  }
  const out = new Float64Array(3 * parts);
  for (let i = 0; i < parts; i++) for (let k = 0; k < 3; k++) out[3 * i + k] = area[i] > 0 ? sum[3 * i + k] / area[i] : NaN;
  return out;
}

/**
 * The print direction of each part from report.multidir.parts (unit; +Z when missing).
 * @returns {Float64Array} #parts*3
 */
export function partDirections(m, parts) {
  const out = new Float64Array(3 * parts);
  const list = m && Array.isArray(m.parts) ? m.parts : [];
  for (let i = 0; i < parts; i++) {
    const p = list.find((q) => q && q.print_index === i) || list[i];
    const d = p && Array.isArray(p.direction) && p.direction.length === 3 ? p.direction.map(Number) : [0, 0, 1];
    const len = Math.hypot(...d);
    const u = len > 0 && d.every(Number.isFinite) ? d.map((x) => x / len) : [0, 0, 1];
    out.set(u, 3 * i);
  }
  return out;
}

/**
 * Arrows along the parts' directions from their centroids: a shaft and two head strokes (in the
 * plane of the direction and a perpendicular) per part, as line segments (6 numbers each), 3
 * segments per part in print order. Parts without a centroid get zero-length segments.
 * @returns {Float32Array} #parts*3*6
 */
export function arrowSegments(centroids, directions, length) {
  const parts = directions.length / 3;
  const out = new Float32Array(parts * 18);
  for (let i = 0; i < parts; i++) {
    const c = [centroids[3 * i], centroids[3 * i + 1], centroids[3 * i + 2]];
    if (!c.every(Number.isFinite)) continue;
    const d = [directions[3 * i], directions[3 * i + 1], directions[3 * i + 2]];
    // A unit perpendicular: d x X, or d x Y when d is near X.
    const ref = Math.abs(d[0]) < 0.9 ? [1, 0, 0] : [0, 1, 0];
    let p = [d[1] * ref[2] - d[2] * ref[1], d[2] * ref[0] - d[0] * ref[2], d[0] * ref[1] - d[1] * ref[0]];
    const pl = Math.hypot(...p);
    p = p.map((x) => x / pl);
    const tip = c.map((x, k) => x + length * d[k]);
    const head = 0.25 * length;
    const wing = (s) => tip.map((x, k) => x - head * d[k] + s * 0.5 * head * p[k]);
    const segs = [[c, tip], [tip, wing(1)], [tip, wing(-1)]];
    segs.forEach(([a, b], s) => out.set([...a, ...b], 18 * i + 6 * s));
  }
  return out;
}

/**
 * Index list of the flagged triangles of an indexed mesh (flags: one per triangle).
 * @returns {Uint32Array} 3 vertex indices per flagged triangle
 */
export function flaggedTriangles(indices, flags) {
  let n = 0;
  for (let t = 0; t < flags.length; t++) if (flags[t]) n++;
  const out = new Uint32Array(3 * n);
  let o = 0;
  for (let t = 0; t < flags.length; t++) {
    if (!flags[t]) continue;
    out[o++] = indices[3 * t];
    out[o++] = indices[3 * t + 1];
    out[o++] = indices[3 * t + 2];
  }
  return out;
}

/** Summed area (mm^2) of the flagged triangles of an indexed mesh. */
export function flaggedArea(positions, indices, flags) {
  let sum = 0;
  for (let t = 0; t < flags.length; t++) {
    if (!flags[t]) continue;
    const a = 3 * indices[3 * t], b = 3 * indices[3 * t + 1], c = 3 * indices[3 * t + 2];
    const ux = positions[b] - positions[a], uy = positions[b + 1] - positions[a + 1], uz = positions[b + 2] - positions[a + 2];
    const vx = positions[c] - positions[a], vy = positions[c + 1] - positions[a + 1], vz = positions[c + 2] - positions[a + 2];
    sum += 0.5 * Math.hypot(uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx);
  }
  return sum;
}

/**
 * Geometry of the J_G-per-search-level chart (SVG units): a polyline with a dot per level
 * (level 0 = before any plane), y from 0 to the largest value, ticks.
 * @param {number[]} values J_G (mm^2) after each level, report.multidir.search.J_G_per_level
 * @returns {{plot: {x, y, width, height}, points: {x, y, level, value}[], path: string,
 *   yTicks: {y, value}[], xTicks: {x, value}[], maxValue: number}}
 * @throws Error when a value is not a finite number >= 0
 */
export function jgChartGeometry(values, { width = 260, height = 110 } = {}) {
  const list = Array.isArray(values) ? values : [];
  list.forEach((v, k) => {
    if (typeof v !== 'number' || !Number.isFinite(v) || v < 0) throw new Error(`J_G of level ${k} is not a number >= 0`);
  });
  const plot = { x: 34, y: 6, width: width - 40, height: height - 24 };
  const maxValue = list.length ? Math.max(...list) : 0;
  const top = maxValue > 0 ? maxValue : 1;
  const n = list.length;
  const xOf = (k) => plot.x + (n > 1 ? (k / (n - 1)) * plot.width : plot.width / 2);
  const yOf = (v) => plot.y + plot.height * (1 - v / top);
  const points = list.map((v, k) => ({ x: xOf(k), y: yOf(v), level: k, value: v }));
  const path = points.map((p, k) => `${k ? 'L' : 'M'}${p.x.toFixed(2)},${p.y.toFixed(2)}`).join(' ');
  const yTicks = niceTicks(0, top, 3).map((v) => ({ y: yOf(v), value: v }));
  const xTicks = points.filter((p, k) => n <= 8 || k % Math.ceil(n / 8) === 0 || k === n - 1).map((p) => ({ x: p.x, value: p.level }));
  return { plot, points, path, yTicks, xTicks, maxValue };
}

/**
 * A progress event's search level is well formed: a line name (workers/protocol.js SEARCH_LINES;
 * not imported: the page's own modules load without the engine's), level >= 0, J_G >= 0.
 */
function validLevel(s) {
  return !!s && typeof s.line === 'string' && s.line !== '' && Number.isInteger(s.level) && s.level >= 0
    && typeof s.J_G === 'number' && Number.isFinite(s.J_G) && s.J_G >= 0;
}

/**
 * One line on a search-level progress event (progress.search {line, level, J_G, beams}):
 * "search level 3: J_G = 1.25 mm² (beam, 8 beams)"; the returned sequence's levels end in
 * "(chosen)". Empty for anything else.
 */
export function searchLevelText(s) {
  if (!validLevel(s)) return '';
  const beams = Number(s.beams);
  const tail = s.line === 'chosen' || !(beams > 0) ? s.line : `${s.line}, ${figure(beams)} beam${beams === 1 ? '' : 's'}`;
  return `search level ${s.level}: J_G = ${areaFigure(s.J_G)} mm² (${tail})`;
}

/**
 * The live J_G chart of a running search from its level events (in arrival order): once the
 * search has reported its chosen sequence, J_G after each of its levels (what
 * report.multidir.search.J_G_per_level will hold); before that, at each level k the least J_G
 * found so far with at most k planes by the greedy, constrained and beam lines (the 4dof axis
 * screening runs on a coarse grid and only ranks axes: left out).
 * @param {{line, level, J_G}[]} events progress.search of every event so far
 * @returns {number[]} J_G (mm²) per level, level 0 first; [] without a usable event
 */
export function liveJgLevels(events) {
  const list = (Array.isArray(events) ? events : []).filter(validLevel);
  const chosenStart = list.findLastIndex((s) => s.line === 'chosen' && s.level === 0);
  if (chosenStart >= 0) {
    const out = [];
    for (const s of list.slice(chosenStart)) if (s.line === 'chosen' && s.level === out.length) out.push(s.J_G);
    return out;
  }
  const least = [];
  for (const s of list) {
    if (s.line === 'screen' || s.line === 'chosen') continue;
    least[s.level] = least[s.level] === undefined ? s.J_G : Math.min(least[s.level], s.J_G);
  }
  const out = [];
  let best = Infinity;
  for (let k = 0; k < least.length; k++) {
    if (least[k] !== undefined) best = Math.min(best, least[k]);
    if (best === Infinity) return [];
    out.push(best);
  }
  return out;
}

/** An area (mm²) as text, to 0.01 mm² (exact J_G values carry rounding noise around 0). */
export function areaFigure(x) {
  return Number.isFinite(x) ? figure(Math.round(x * 100) / 100) : '—';
}

/** The figures of report.multidir as [key, label, text] rows. */
export function multidirSummaryRows(m) {
  const r = m && typeof m === 'object' ? m : {};
  const s = r.search && typeof r.search === 'object' ? r.search : {};
  const t = r.timings_ms && typeof r.timings_ms === 'object' ? r.timings_ms : {};
  const pct = Number.isFinite(r.ratio) ? ` (${figure(Math.round(1000 * r.ratio) / 10)} %)` : '';
  const axis = Array.isArray(r.rotation_axis) ? `, axis (${r.rotation_axis.map((x) => figure(Number(Number(x).toFixed(3)))).join(', ')})` : '';
  return [
    ['jg', 'risky area J_G', `${areaFigure(r.J_G_before)} mm² → ${areaFigure(r.J_G_after)} mm²${pct}`],
    ['parts', 'parts', figure(r.part_count)],
    ['search', 'search', `${r.scheme || '?'}, ${r.dof || '?'}${axis}, α_max ${withUnit(r.alpha_max_deg, '°')}`],
    ['levels', 'levels, beams, restarts', `${figure(s.levels)}, ${figure(s.beams)}, ${figure(s.restarts_run)}`],
    ['moves', 'local search moves kept', `${figure(s.perturbations_kept)} of ${figure(s.perturbations)}`],
    ['candidates', 'candidates evaluated', figure(s.candidates_evaluated)],
    ['cap_area', 'cut area', withUnit(r.cap_area_mm2, 'mm²')],
    ['volume', 'volume', withUnit(r.volume_mm3, 'mm³')],
    ['time', 'search, clip', `${formatMs(t.search ?? t.decompose)}, ${formatMs(t.clip)}`],
    ['supports', 'projected supports', supportText(r.supports)],
  ];
}

/** One line on a report's support object (multidir.supports or the planar report.support). */
export function supportText(sup) {
  if (!sup || typeof sup !== 'object' || !sup.generated) return 'off';
  const blocked = Number(sup.blocked) > 0 ? `, ${figure(sup.blocked)} blocked` : '';
  return `${withUnit(Math.round(Number(sup.printed_volume_mm3) * 10) / 10, 'mm³')} printed: ${figure(sup.struts)} struts `
    + `from ${figure(sup.samples)} overhang samples (${figure(sup.landed_on_platform)} to the platform, `
    + `${figure(sup.landed_on_model)} on the part${blocked}), ${figure(sup.roofs)} roof faces`;
}

/** The parts table of report.multidir: one row per part in print order. */
export function partRows(m) {
  const list = m && Array.isArray(m.parts) ? m.parts : [];
  return list.map((p, k) => {
    const index = Number.isInteger(p.print_index) ? p.print_index : k;
    const d = Array.isArray(p.direction) ? p.direction.map(Number) : [0, 0, 1];
    const tilt = (Math.acos(Math.min(1, Math.max(-1, d[2] / (Math.hypot(...d) || 1)))) * 180) / Math.PI;
    return {
      index,
      direction: `(${d.map((x) => (Math.abs(x) < 5e-4 ? '0' : x.toFixed(3))).join(', ')})`,
      tiltDeg: tilt,
      volume: Number(p.volume_mm3),
      risky: Math.round(100 * Number(p.risky_area_mm2)) / 100,
      layers: Number(p.layers),
      platform: p.plane === null || p.plane === undefined,
      support: Number.isFinite(Number(p.support_region_mm3)) ? Number(p.support_region_mm3) : 0,
    };
  });
}

/** The one-line summary after a multidir slice. */
export function multidirDoneSummary(m) {
  if (!m || typeof m !== 'object') return '';
  return `${figure(m.part_count)} parts, J_G ${areaFigure(m.J_G_before)} → ${areaFigure(m.J_G_after)} mm²`;
}
