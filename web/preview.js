// SPDX-License-Identifier: MIT
// Tool-path preview: the worker's preview buffers drawn as LineSegments coloured by feature, with a
// layer range shown through drawRange. Built from typed arrays in a few linear passes (no per-segment
// JS objects), so ~1M segments take tens of milliseconds:
//   - the position buffer is used as is (one GPU upload, shared by the two objects below);
//   - one Uint8 colour per vertex from a small palette (by feature; segments on an iso-planar NL
//     curve, preview.curves > 0, alternate between two colours curve by curve so the side steps
//     between adjacent curves show);
//   - two index buffers (extruding moves, travel moves), each counting-sorted by layer, with
//     per-layer start offsets, so a layer range [lo, hi] is one contiguous drawRange;
//   - the per-segment passes run in blocks and yield every ~12 ms (no long main-thread task).
import * as THREE from 'three';

import { blockRunner } from './block-runner.js';
import { rgbCss } from './colors.js';
import { CURVE_COLORS } from './methods/isoplanar-data.js';

/** Feature codes of the preview buffers (PROGRAM-FORMAT.md names). */
export const FEATURES = [
  { code: 0, name: 'travel', color: [0x5a, 0x6a, 0x80] },
  { code: 1, name: 'wall-outer', color: [0xe8, 0x4a, 0x3c] },
  { code: 2, name: 'wall-inner', color: [0xf2, 0xc1, 0x3b] },
  { code: 3, name: 'skin', color: [0x9b, 0x6b, 0xe8] },
  { code: 4, name: 'infill', color: [0x2f, 0xb0, 0x9a] },
  { code: 5, name: 'support', color: [0x5a, 0xa8, 0xf0] },
  { code: 6, name: 'bridge', color: [0x8c, 0xd8, 0x4c] },
];

/** CSS colour of a feature code, for legends. */
export function featureCss(code) {
  const f = FEATURES[code] || FEATURES[0];
  return rgbCss(f.color);
}

/**
 * Colours and layer-sorted index buffers of preview buffers, built in blocks of `block` segments;
 * whenever a task has run for `budgetMs` it yields, so no single task runs long (the first blocks
 * run before the JIT has optimised the loops, so a time budget beats a fixed slice size).
 * Printing segments on an NL curve (curves[s] > 0, when curves has one entry per segment) take
 * CURVE_COLORS[(curves[s] - 1) % 2] instead of their feature's colour.
 * @returns {Promise<{layerCount: number, colors: Uint8Array, featureCounts: Uint32Array, curveCount: number,
 *   curveLayerMin: number (lowest layer with a segment on an NL curve, -1 without),
 *   print: {index: Uint32Array, starts: Uint32Array}, travel: {index: Uint32Array,
 *   starts: Uint32Array}}>} index: 2 vertex indices per segment, counting-sorted by layer (stable:
 *   print order within a layer); starts[l]..starts[l+1] is layer l's range in segments
 *   (layerCount+1 entries)
 */
export async function buildPreviewArrays({ features, layers, curves }, { budgetMs = 12, block = 4096 } = {}) {
  const S = features.length;
  const onCurves = curves && curves.length === S ? curves : null;
  let curveCount = 0;
  let curveLayerMin = -1;
  // Run fn(from, to) over [0, S) in blocks, yielding when the task has used its budget.
  const run = blockRunner('omnislice:preview-slice', { budgetMs, block });
  const forBlocks = (fn) => run(S, fn);
  let maxLayer = -1;
  await forBlocks((from, to) => {
    for (let s = from; s < to; s++) if (layers[s] > maxLayer) maxLayer = layers[s];
  });
  const layerCount = maxLayer + 1;
  const printStarts = new Uint32Array(layerCount + 1);
  const travelStarts = new Uint32Array(layerCount + 1);
  const featureCounts = new Uint32Array(256);
  await forBlocks((from, to) => {
    for (let s = from; s < to; s++) {
      featureCounts[features[s]]++;
      if (features[s] === 0) travelStarts[layers[s] + 1]++;
      else printStarts[layers[s] + 1]++;
    }
  });
  for (let l = 0; l < layerCount; l++) {
    printStarts[l + 1] += printStarts[l];
    travelStarts[l + 1] += travelStarts[l];
  }
  const printIndex = new Uint32Array(printStarts[layerCount] * 2);
  const travelIndex = new Uint32Array(travelStarts[layerCount] * 2);
  const printCursor = printStarts.slice(0, layerCount);
  const travelCursor = travelStarts.slice(0, layerCount);
  const colors = new Uint8Array(S * 6);
  const palette = new Uint8Array(256 * 3);
  for (let c = 0; c < 256; c++) palette.set((FEATURES[c] || FEATURES[0]).color, c * 3);
  const curvePalette = new Uint8Array([...CURVE_COLORS[0], ...CURVE_COLORS[1]]);
  await forBlocks((from, to) => {
    for (let s = from; s < to; s++) {
      const f = features[s];
      const c = onCurves && f !== 0 ? onCurves[s] : 0;
      let p = f * 3;
      let pal = palette;
      if (c > 0) {
        if (c > curveCount) curveCount = c;
        if (curveLayerMin < 0 || layers[s] < curveLayerMin) curveLayerMin = layers[s];
        p = ((c - 1) % 2) * 3;
        pal = curvePalette;
      }
      const o = s * 6;
      colors[o] = colors[o + 3] = pal[p];
      colors[o + 1] = colors[o + 4] = pal[p + 1];
      colors[o + 2] = colors[o + 5] = pal[p + 2];
      let k;
      let index;
      if (f === 0) {
        k = travelCursor[layers[s]]++;
        index = travelIndex;
      } else {
        k = printCursor[layers[s]]++;
        index = printIndex;
      }
      index[2 * k] = 2 * s;
      index[2 * k + 1] = 2 * s + 1;
    }
  });
  run.end();
  return {
    layerCount,
    colors,
    featureCounts,
    curveCount,
    curveLayerMin,
    print: { index: printIndex, starts: printStarts },
    travel: { index: travelIndex, starts: travelStarts },
  };
}

export class ToolpathPreview {
  /**
   * Build a preview without holding the main thread (see buildPreviewArrays).
   * @param {{positions: Float32Array, features: Uint8Array, layers: Uint32Array, curves?: Uint32Array}} preview
   *   #S*6 segment end points (part frame, mm), #S feature codes, #S layer indices, #S NL curve
   *   indices (1-based, 0 = none; optional)
   */
  static async build(preview, options) {
    const { positions, features, layers } = preview;
    const S = features.length;
    if (positions.length !== S * 6 || layers.length !== S) {
      throw new Error(`preview buffers disagree: ${positions.length / 6} segments of positions, ${S} features, ${layers.length} layers`);
    }
    return new ToolpathPreview(positions, await buildPreviewArrays(preview, options));
  }

  /** Use ToolpathPreview.build(); this takes the arrays it prepares. */
  constructor(positions, arrays) {
    this.layerCount = arrays.layerCount;
    this.segmentCount = positions.length / 6;
    /** Segments per feature name (travel, wall-outer, ...), e.g. for a legend. */
    this.featureCounts = Object.fromEntries(FEATURES.map((f) => [f.name, arrays.featureCounts[f.code]]));
    /** Highest NL curve index drawn in the curve colours (0: no iso-planar curves). */
    this.curveCount = arrays.curveCount;
    /** Lowest layer holding NL curve segments (-1 without), e.g. to start the layer range there. */
    this.curveLayerMin = arrays.curveLayerMin;
    this.printStarts = arrays.print.starts;
    this.travelStarts = arrays.travel.starts;
    const position = new THREE.BufferAttribute(positions, 3);
    const color = new THREE.BufferAttribute(arrays.colors, 3, true);
    const makeLines = (index, opacity, name) => {
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', position);
      g.setAttribute('color', color);
      g.setIndex(new THREE.BufferAttribute(index, 1));
      // Never culled (frustumCulled = false): no bounding pass over millions of vertices here.
      const m = new THREE.LineBasicMaterial({ vertexColors: true, transparent: opacity < 1, opacity });
      const lines = new THREE.LineSegments(g, m);
      lines.name = name;
      lines.frustumCulled = false;
      return lines;
    };
    this.printLines = makeLines(arrays.print.index, 1, 'preview-print');
    this.travelLines = makeLines(arrays.travel.index, 0.35, 'preview-travel');
    this.travelLines.visible = false;
    this.object = new THREE.Group();
    this.object.name = 'preview';
    this.object.add(this.printLines, this.travelLines);
    this.range = [0, Math.max(this.layerCount - 1, 0)];
    this.setLayerRange(0, this.layerCount - 1);
  }

  /** Show layers lo..hi inclusive (clamped). */
  setLayerRange(lo, hi) {
    const last = Math.max(this.layerCount - 1, 0);
    lo = Math.min(Math.max(0, Math.floor(lo)), last);
    hi = Math.min(Math.max(lo, Math.floor(hi)), last);
    this.range = [lo, hi];
    for (const [lines, starts] of [[this.printLines, this.printStarts], [this.travelLines, this.travelStarts]]) {
      const from = this.layerCount ? starts[lo] : 0;
      const to = this.layerCount ? starts[hi + 1] : 0;
      lines.geometry.setDrawRange(from * 2, (to - from) * 2);
    }
  }

  /** Number of segments currently drawn (print, travel), for tests and the status line. */
  drawnSegments() {
    return [this.printLines.geometry.drawRange.count / 2, this.travelLines.visible ? this.travelLines.geometry.drawRange.count / 2 : 0];
  }

  setTravelVisible(visible) {
    this.travelLines.visible = visible;
  }
}
