// SPDX-License-Identifier: MIT
// Tool-path preview: the worker's preview buffers drawn as LineSegments coloured by feature, with a
// layer range shown through drawRange. Built from typed arrays in a few linear passes (no per-segment
// JS objects), so ~1M segments take tens of milliseconds:
//   - the position buffer is used as is (one GPU upload, shared by the two objects below);
//   - one Uint8 colour per vertex from a small palette;
//   - two index buffers (extruding moves, travel moves), each counting-sorted by layer, with
//     per-layer start offsets, so a layer range [lo, hi] is one contiguous drawRange.
import * as THREE from 'three';

/** Feature codes of the preview buffers (PROGRAM-FORMAT.md names). */
export const FEATURES = [
  { code: 0, name: 'travel', color: [0x5a, 0x6a, 0x80] },
  { code: 1, name: 'wall-outer', color: [0xf0, 0x5a, 0x3c] },
  { code: 2, name: 'wall-inner', color: [0xf2, 0xc1, 0x3b] },
  { code: 3, name: 'skin', color: [0x9b, 0x6b, 0xe8] },
  { code: 4, name: 'infill', color: [0xe0, 0x8a, 0x2e] },
  { code: 5, name: 'support', color: [0x3c, 0xc8, 0xd8] },
  { code: 6, name: 'bridge', color: [0x4c, 0xd1, 0x6e] },
];

/** CSS colour of a feature code, for legends. */
export function featureCss(code) {
  const f = FEATURES[code] || FEATURES[0];
  return `rgb(${f.color.join(',')})`;
}

/**
 * Group segment indices by layer (counting sort, stable in print order).
 * @param {Uint32Array} layers #S layer index per segment
 * @param {(s: number) => boolean} keep which segments belong to the group
 * @param {number} layerCount layers (max index + 1)
 * @returns {{index: Uint32Array, starts: Uint32Array}} index: 2 vertex indices per kept segment,
 *   layer-sorted; starts[l]..starts[l+1] is layer l's range in segments (starts has layerCount+1 entries)
 */
export function groupByLayer(layers, keep, layerCount) {
  const starts = new Uint32Array(layerCount + 1);
  const S = layers.length;
  for (let s = 0; s < S; s++) if (keep(s)) starts[layers[s] + 1]++;
  for (let l = 0; l < layerCount; l++) starts[l + 1] += starts[l];
  const total = starts[layerCount];
  const index = new Uint32Array(total * 2);
  const cursor = starts.slice(0, layerCount);
  for (let s = 0; s < S; s++) {
    if (!keep(s)) continue;
    const k = cursor[layers[s]]++;
    index[2 * k] = 2 * s;
    index[2 * k + 1] = 2 * s + 1;
  }
  return { index, starts };
}

export class ToolpathPreview {
  /**
   * @param {{positions: Float32Array, features: Uint8Array, layers: Uint32Array}} preview
   *   #S*6 segment end points (part frame, mm), #S feature codes, #S layer indices
   */
  constructor(preview) {
    const { positions, features, layers } = preview;
    const S = features.length;
    if (positions.length !== S * 6 || layers.length !== S) {
      throw new Error(`preview buffers disagree: ${positions.length / 6} segments of positions, ${S} features, ${layers.length} layers`);
    }
    let maxLayer = -1;
    for (let s = 0; s < S; s++) if (layers[s] > maxLayer) maxLayer = layers[s];
    this.layerCount = maxLayer + 1;
    this.segmentCount = S;

    const colors = new Uint8Array(S * 6);
    const palette = FEATURES.map((f) => f.color);
    for (let s = 0; s < S; s++) {
      const c = palette[features[s]] || palette[0];
      const o = s * 6;
      colors[o] = colors[o + 3] = c[0];
      colors[o + 1] = colors[o + 4] = c[1];
      colors[o + 2] = colors[o + 5] = c[2];
    }
    const position = new THREE.BufferAttribute(positions, 3);
    const color = new THREE.BufferAttribute(colors, 3, true);

    const print = groupByLayer(layers, (s) => features[s] !== 0, this.layerCount);
    const travel = groupByLayer(layers, (s) => features[s] === 0, this.layerCount);
    this.printStarts = print.starts;
    this.travelStarts = travel.starts;

    const makeLines = (index, opacity, name) => {
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', position);
      g.setAttribute('color', color);
      g.setIndex(new THREE.BufferAttribute(index, 1));
      g.computeBoundingSphere();
      const m = new THREE.LineBasicMaterial({ vertexColors: true, transparent: opacity < 1, opacity });
      const lines = new THREE.LineSegments(g, m);
      lines.name = name;
      lines.frustumCulled = false;
      return lines;
    };
    this.printLines = makeLines(print.index, 1, 'preview-print');
    this.travelLines = makeLines(travel.index, 0.35, 'preview-travel');
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
