// SPDX-License-Identifier: MIT
// Pure data preparation for the voxel method's view (no three.js, no DOM; unit-tested in Node):
//   - the method's progress stages and their share of the progress bar;
//   - curved layer surfaces: the merged triangle soup (surfacePositions, surfaceTriangles,
//     surfaceLayers) de-indexed and counting-sorted by layer, with a colour per layer, so "layers
//     lo..hi-1 dimmed, layer hi highlighted" are two contiguous draw ranges;
//   - nozzle-axis glyphs: a decimated subset of the printing segment ends (even spacing along the
//     printed path), each a short segment along the segment's axis, sorted by layer;
//   - the layer-thickness histogram of report.voxel.thickness as bar geometry (SVG units; the
//     core bins each sample's thickness minus the mean thickness);
//   - the voxel report's summary rows.

import { blockRunner } from '../block-runner.js';
import { hslToRgb } from '../colors.js';
import { figure, formatMm, formatMs, niceTicks, withUnit } from '../format.js';

/** Progress stages of a voxel slice, in pipeline order, with their share of the bar (sums to 1). */
export const VOXEL_STAGE_WEIGHTS = Object.freeze({
  read: 0.02, validate: 0.03, place: 0.01, voxelize: 0.06, peeling: 0.12, growth: 0.3,
  layers: 0.16, toolpath: 0.17, motion: 0.08, program: 0.05,
});

/**
 * Colour of layer l of L (0..255 RGB): hue from blue (first) to red (last), lightness
 * alternating between neighbours so adjacent layers stay distinguishable.
 */
export function layerColor(l, L) {
  const t = L > 1 ? Math.min(Math.max(l / (L - 1), 0), 1) : 0;
  return hslToRgb(225 - 215 * t, 0.62, l % 2 ? 0.6 : 0.47);
}

/** Colour of the highlighted (current) layer. */
export const CURRENT_LAYER_COLOR = [0xff, 0xf2, 0x9e];

/**
 * De-index the layer surfaces and sort their triangles by layer (stable: soup order within a layer).
 * @param {{surfacePositions: Float32Array, surfaceTriangles: Uint32Array, surfaceLayers: Uint32Array}} p
 *   #V*3 positions (mm), #T*3 vertex indices, #T layer indices
 * @returns {Promise<{layerCount: number, triangleCount: number, positions: Float32Array,
 *   colors: Uint8Array, starts: Uint32Array, layers: Uint32Array}>} positions/colors: 9 per
 *   triangle in sorted order; starts[l]..starts[l+1] is layer l's triangle range (layerCount+1
 *   entries); layers: the sorted triangles' layer indices
 * @throws Error when the buffers disagree (lengths, indices out of range)
 */
export async function buildSurfaceArrays(p, options) {
  const P = p.surfacePositions || new Float32Array(0);
  const tri = p.surfaceTriangles || new Uint32Array(0);
  const lay = p.surfaceLayers || new Uint32Array(0);
  const T = lay.length;
  const V = P.length / 3;
  if (P.length % 3 !== 0 || tri.length !== T * 3) {
    throw new Error(`surface buffers disagree: ${P.length / 3} vertices, ${tri.length / 3} triangles of indices, ${T} triangle layers`);
  }
  const run = blockRunner('omnislice:voxel-slice', options);
  let maxLayer = -1;
  let badIndex = -1;
  await run(T, (from, to) => {
    for (let t = from; t < to; t++) {
      if (lay[t] > maxLayer) maxLayer = lay[t];
      for (let k = 3 * t; k < 3 * t + 3; k++) if (tri[k] >= V && badIndex < 0) badIndex = t;
    }
  });
  if (badIndex >= 0) throw new Error(`surface triangle ${badIndex} refers to a vertex beyond the ${V} given`);
  const layerCount = maxLayer + 1;
  const starts = new Uint32Array(layerCount + 1);
  for (let t = 0; t < T; t++) starts[lay[t] + 1]++;
  for (let l = 0; l < layerCount; l++) starts[l + 1] += starts[l];
  const cursor = starts.slice(0, layerCount);
  const palette = new Uint8Array(Math.max(layerCount, 1) * 3);
  for (let l = 0; l < layerCount; l++) palette.set(layerColor(l, layerCount), l * 3);
  const positions = new Float32Array(T * 9);
  const colors = new Uint8Array(T * 9);
  const layers = new Uint32Array(T);
  await run(T, (from, to) => {
    for (let t = from; t < to; t++) {
      const l = lay[t];
      const k = cursor[l]++;
      layers[k] = l;
      for (let c = 0; c < 3; c++) {
        const v = tri[3 * t + c];
        const o = 9 * k + 3 * c;
        positions[o] = P[3 * v];
        positions[o + 1] = P[3 * v + 1];
        positions[o + 2] = P[3 * v + 2];
        colors[o] = palette[3 * l];
        colors[o + 1] = palette[3 * l + 1];
        colors[o + 2] = palette[3 * l + 2];
      }
    }
  });
  run.end();
  return { layerCount, triangleCount: T, positions, colors, starts, layers };
}

/**
 * Draw ranges (in triangles) of the layer surfaces for the layer range lo..hi: `below` covers
 * layers lo..hi-1, `current` layer hi. Bounds are clamped to the layers present.
 */
export function surfaceRanges(starts, lo, hi) {
  const L = starts.length - 1;
  if (L <= 0) return { lo: 0, hi: 0, below: { start: 0, count: 0 }, current: { start: 0, count: 0 } };
  const last = L - 1;
  const a = Math.min(Math.max(0, Math.floor(Number(lo) || 0)), last);
  const b = Math.min(Math.max(a, Math.floor(Number(hi) || 0)), last);
  return {
    lo: a,
    hi: b,
    below: { start: starts[a], count: starts[b] - starts[a] },
    current: { start: starts[b], count: starts[b + 1] - starts[b] },
  };
}

/**
 * Nozzle-axis glyphs at a decimated subset of the printing segments' end points: walking the
 * printing segments (feature != 0) in print order, a glyph is placed at the end of the segment
 * where the printed length passes the next multiple of `spacing` (default: total printed length /
 * maxGlyphs, so at most about maxGlyphs glyphs, evenly spread along the path). Segments with a
 * zero or non-finite axis get none.
 * @param {{positions: Float32Array, features: Uint8Array, layers: Uint32Array, axes: Float32Array}} p
 *   #S*6 segment ends, #S features, #S layers, #S*3 unit nozzle axes at the segment ends
 * @param {{maxGlyphs?: number, length?: number, spacing?: number}} [options] length: glyph length, mm
 * @returns {Promise<{count: number, positions: Float32Array, segments: Uint32Array, layers: Uint32Array,
 *   starts: Uint32Array, layerCount: number, spacing: number}>} (built in blocks, yielding like
 *   buildSurfaceArrays) positions: 6 per glyph (start =
 *   segment end, end = start + length * axis), sorted by layer (stable); segments: the segment
 *   index of each glyph; starts: per-layer glyph ranges (layerCount + 1 entries)
 */
export async function decimateGlyphs(p, { maxGlyphs = 4000, length = 2, spacing, budgetMs, block } = {}) {
  const { positions, features, layers } = p;
  const axes = p.axes || new Float32Array(0);
  const S = features.length;
  const empty = { count: 0, positions: new Float32Array(0), segments: new Uint32Array(0), layers: new Uint32Array(0), starts: new Uint32Array(1), layerCount: 0, spacing: 0 };
  if (axes.length !== S * 3 || positions.length !== S * 6 || layers.length !== S || S === 0 || !(maxGlyphs >= 1)) return empty;
  const segLength = (s) => {
    const o = 6 * s;
    const dx = positions[o + 3] - positions[o];
    const dy = positions[o + 4] - positions[o + 1];
    const dz = positions[o + 5] - positions[o + 2];
    return Math.sqrt(dx * dx + dy * dy + dz * dz);
  };
  const run = blockRunner('omnislice:voxel-slice', { budgetMs, block: block || 65536 });
  let total = 0;
  let layerCount = 0;
  await run(S, (from, to) => {
    for (let s = from; s < to; s++) {
      if (features[s] === 0) continue;
      total += segLength(s);
      if (layers[s] + 1 > layerCount) layerCount = layers[s] + 1;
    }
  });
  if (!(total > 0)) return empty;
  const step = spacing > 0 ? spacing : total / maxGlyphs;
  const picked = [];
  let walked = 0;
  let next = 0;  // the first printing segment gets a glyph
  await run(S, (from, to) => {
    for (let s = from; s < to; s++) {
      if (features[s] === 0) continue;
      walked += segLength(s);
      if (walked < next) continue;
      const ax = axes[3 * s];
      const ay = axes[3 * s + 1];
      const az = axes[3 * s + 2];
      const n = Math.sqrt(ax * ax + ay * ay + az * az);
      if (!(n > 1e-9) || !Number.isFinite(n)) continue;
      picked.push(s);
      next = (Math.floor(walked / step) + 1) * step;
    }
  });
  run.end();
  const G = picked.length;
  const starts = new Uint32Array(layerCount + 1);
  for (const s of picked) starts[layers[s] + 1]++;
  for (let l = 0; l < layerCount; l++) starts[l + 1] += starts[l];
  const cursor = starts.slice(0, layerCount);
  const out = new Float32Array(G * 6);
  const segs = new Uint32Array(G);
  const outLayers = new Uint32Array(G);
  for (const s of picked) {
    const k = cursor[layers[s]]++;
    const n = Math.hypot(axes[3 * s], axes[3 * s + 1], axes[3 * s + 2]);
    segs[k] = s;
    outLayers[k] = layers[s];
    for (let c = 0; c < 3; c++) {
      out[6 * k + c] = positions[6 * s + 3 + c];
      out[6 * k + 3 + c] = positions[6 * s + 3 + c] + (length * axes[3 * s + c]) / n;
    }
  }
  return { count: G, positions: out, segments: segs, layers: outLayers, starts, layerCount, spacing: step };
}

/**
 * Glyph draw range (in glyphs) for the layer range lo..hi, clamped.
 */
export function glyphRange(starts, lo, hi) {
  const L = starts.length - 1;
  if (L <= 0) return { start: 0, count: 0 };
  const a = Math.min(Math.max(0, Math.floor(lo)), L - 1);
  const b = Math.min(Math.max(a, Math.floor(hi)), L - 1);
  return { start: starts[a], count: starts[b + 1] - starts[a] };
}

/**
 * Bars of a histogram {min_mm, bin_mm, counts} in a width x height box (SVG user units, y down):
 * bar i spans [min + i bin, min + (i+1) bin) and is counts[i] / max(counts) of the plot's height.
 * @returns {{bars: {x, y, width, height, count, from, to}[], total: number, maxCount: number,
 *   plot: {x, y, width, height}, ticks: {x, label, value}[]}} ticks: round values (1, 2 or 5
 *   times a power of ten apart) within the bins' span
 * @throws Error when the histogram is malformed
 */
export function histogramGeometry(hist, { width = 260, height = 110, padLeft = 6, padRight = 6, padTop = 6, padBottom = 18, ticks = 5 } = {}) {
  if (!hist || typeof hist !== 'object') throw new Error('histogram: missing');
  const min = Number(hist.min_mm);
  const bin = Number(hist.bin_mm);
  const counts = Array.isArray(hist.counts) || ArrayBuffer.isView(hist.counts) ? Array.from(hist.counts, Number) : null;
  if (!Number.isFinite(min)) throw new Error('histogram: min_mm is not a number');
  if (!(bin > 0) || !Number.isFinite(bin)) throw new Error('histogram: bin_mm must be a positive number');
  if (!counts || counts.some((c) => !(c >= 0) || !Number.isFinite(c))) throw new Error('histogram: counts must be non-negative numbers');
  const plot = { x: padLeft, y: padTop, width: Math.max(width - padLeft - padRight, 1), height: Math.max(height - padTop - padBottom, 1) };
  const n = counts.length;
  const maxCount = n ? Math.max(...counts) : 0;
  const total = counts.reduce((a, b) => a + b, 0);
  const bw = n ? plot.width / n : 0;
  const bars = counts.map((count, i) => {
    const h = maxCount > 0 ? (count / maxCount) * plot.height : 0;
    return { x: plot.x + i * bw, y: plot.y + plot.height - h, width: bw, height: h, count, from: min + i * bin, to: min + (i + 1) * bin };
  });
  // Ticks at round values (1, 2 or 5 times a power of ten), about `ticks` of them.
  const lo = min;
  const hi = min + n * bin;
  const tickList = n > 0
    ? niceTicks(lo, hi, ticks).map((v) => ({ x: plot.x + ((v - lo) / (hi - lo)) * plot.width, label: formatMm(v), value: v }))
    : [];
  return { bars, total, maxCount, plot, ticks: tickList };
}

/**
 * The motion term's row (motion.axis_freedom_deg): how many samples' nozzle axes lean from their
 * ideal axis to keep the rotary axes still, and by at most how much; none when the report has no
 * such figure (older reports).
 */
export function axesFreedRows(r) {
  if (!r || !Number.isFinite(r.axes_freed)) return [];
  const bound = Number.isFinite(r.axis_freedom_deg) ? ` (≤ ${figure(r.axis_freedom_deg)}°)` : '';
  return [['axes_freed', 'axes leaning for motion', `${figure(r.axes_freed)}${bound}`]];
}

/**
 * Summary rows [key, label, text] of report.voxel (keys double as data-testid suffixes:
 * voxel-<key>), in display order; absent figures show '—'.
 */
export function voxelSummaryRows(v) {
  const r = v && typeof v === 'object' ? v : {};
  const t = r.timings_ms && typeof r.timings_ms === 'object' ? r.timings_ms : {};
  const th = r.thickness && typeof r.thickness === 'object' ? r.thickness : {};
  const mm = (x) => withUnit(x, 'mm', formatMm);
  return [
    ['voxels', 'voxels', figure(r.voxels)],
    ['solid_voxels', 'solid voxels', figure(r.solid_voxels)],
    ['missed_voxels', 'missed voxels', figure(r.missed_voxels)],
    ['support_voxels', 'support voxels', figure(r.support_voxels)],
    ...(r.missed_before_supports !== undefined ? [['missed_before_supports', 'missed before supports', figure(r.missed_before_supports)]] : []),
    ...(r.support_rounds !== undefined ? [['support_rounds', 'support rounds', figure(r.support_rounds)]] : []),
    ['field_layers', 'field layers (max G)', figure(r.field_layers)],
    ...(r.layer_field !== undefined ? [['layer_field', 'layers follow', String(r.layer_field)]] : []),
    ['layers', 'curved layers', figure(r.layers)],
    ...(r.surface_layers !== undefined ? [['surface_layers', 'layer surfaces', figure(r.surface_layers)]] : []),
    ['regions', 'regions', figure(r.regions)],
    ...(r.unfilled_regions !== undefined ? [['unfilled_regions', 'unfilled regions', figure(r.unfilled_regions)]] : []),
    ...(r.paths !== undefined ? [['paths', 'spiral paths', figure(r.paths)]] : []),
    ['strategy', 'strategy', r.strategy ? String(r.strategy) : '—'],
    ['shadow_scheme', 'shadow prevention', r.shadow_scheme ? String(r.shadow_scheme) : '—'],
    ['voxel_width_mm', 'voxel width', mm(r.voxel_width_mm)],
    ['iso_step', 'iso step (field units)', figure(r.iso_step)],
    ...(r.target_layer_mm !== undefined ? [['target_layer_mm', 'target layer', mm(r.target_layer_mm)]] : []),
    ['thickness_mean', 'thickness mean', mm(th.mean_mm)],
    ['thickness_std', 'thickness std', mm(th.std_mm)],
    ['thickness_max_dev', 'max deviation', mm(th.max_deviation_mm)],
    ['shadow_checks', 'shadow checks', figure(r.shadow_checks)],
    ['hull_builds', 'hull builds', figure(r.hull_builds)],
    ['orientation_fallbacks', 'orientation fallbacks', figure(r.orientation_fallbacks)],
    ...(r.tilt_clamped !== undefined ? [['tilt_clamped', 'axes clamped to max tilt', figure(r.tilt_clamped)]] : []),
    ...axesFreedRows(r),
    ...['voxelize', 'peeling', 'shadow', 'growth', 'extraction', 'spirals', 'toolpaths']
      .filter((k) => k !== 'spirals' || t.spirals !== undefined)
      .map((k) => [`time_${k}`, `time: ${k}`, formatMs(t[k])]),
  ];
}

/** One line for the progress text after a voxel slice: field layers, layers, regions, missed. */
export function voxelDoneSummary(v) {
  if (!v || typeof v !== 'object') return '';
  return `${figure(v.field_layers)} field layers → ${figure(v.layers)} layers, ${figure(v.regions)} regions, ${figure(v.missed_voxels)} missed`;
}
