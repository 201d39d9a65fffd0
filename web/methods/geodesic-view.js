// SPDX-License-Identifier: MIT
// Three.js objects of the geodesic method's result (paper 002), built from the preview buffers:
//   - the part's boundary surface coloured by the geodesic distance from the platform (the heat
//     method's field), drawn up to the iso-value of the layer slider's top layer (its triangles
//     are sorted by their largest distance, so this is one draw range);
//   - the skeleton tree: one point per IGDS (its centroid, coloured like its layer's surface)
//     and its edges as lines, drawn over the part (no depth test) for the layer range and the
//     print step, the node printed at that step marked;
//   - the air moves of the print sequence (transitions to a node that is not an upper-node of
//     the previous one: the retractions) as lines of their own colour, up to the print step;
//   - the tool path left out where no nozzle axis clears the part (the report's
//     skipped_tool_path warning) as red lines over the part, for the layer range: the gaps the
//     print will have.
// The IGDS surfaces themselves are the curved-layer surfaces of web/voxel-view.js. The data
// preparation is in geodesic-data.js (pure, unit-tested).
import * as THREE from 'three';
import { disposeTree } from '../viewer.js';
import {
  airMoves, checkGeodesicBuffers, fieldColors, fieldTrianglesUpTo, nodeColors, pairSegments, selectTree, sortFieldTriangles,
} from './geodesic-data.js';

/** Colours of the tree's edges, the air moves and the current node's mark. */
export const TREE_EDGE_COLOR = 0xe8edf5;
export const AIR_MOVE_COLOR = 0xff3fa4;
export const CURRENT_NODE_COLOR = 0xffffff;
export const SKIPPED_COLOR = 0xff3b30;

export class GeodesicView {
  /**
   * Build the view of a slice's geodesic buffers (core/pipeline/preview.h, flattened by wasm/helpers.cpp).
   * @param {object} preview fieldPositions, fieldTriangles, fieldValues, nodePositions, nodeLayers,
   *   treeEdges, sequence, skippedSegments and skippedLayers (optional)
   * @param {object} [geodesic] report.geodesic: iso_values_mm (the layers' distances, for the
   *   field's draw range) and layers
   * @throws Error when the buffers disagree (geodesic-data.js checkGeodesicBuffers)
   */
  constructor(preview, geodesic = null) {
    const check = checkGeodesicBuffers(preview);
    const empty = (T) => new T(0);
    const P = preview.fieldPositions || empty(Float32Array);
    const T = preview.fieldTriangles || empty(Uint32Array);
    const values = preview.fieldValues || empty(Float32Array);
    const nodeP = preview.nodePositions || empty(Float32Array);
    const layers = preview.nodeLayers || empty(Uint32Array);
    const edges = preview.treeEdges || empty(Uint32Array);
    const sequence = preview.sequence || empty(Uint32Array);
    const g = geodesic && typeof geodesic === 'object' ? geodesic : {};
    this.isoValues = Array.isArray(g.iso_values_mm) ? g.iso_values_mm.map(Number) : [];
    this.layerCount = Math.max(Number.isFinite(g.layers) ? g.layers : 0, check.layerCount, this.isoValues.length);
    this.nodeCount = check.nodes;
    this.edgeCount = check.edges;
    this.nodeLayers = layers;
    this.rank = check.rank;
    this.sequence = sequence;
    this.treeEdges = edges;

    this.object = new THREE.Group();
    this.object.name = 'geodesic-view';

    // The field on the boundary surface.
    const { colors, min, max } = fieldColors(values);
    this.fieldMin = min;
    this.fieldMax = max;
    const sorted = sortFieldTriangles(T, values);
    this.fieldTriangleCount = check.fieldTriangles;
    this.fieldMaxValues = sorted.maxValues;
    const fg = new THREE.BufferGeometry();
    fg.setAttribute('position', new THREE.BufferAttribute(P, 3));
    fg.setAttribute('color', new THREE.BufferAttribute(colors, 3, true));
    fg.setIndex(new THREE.BufferAttribute(sorted.index, 1));
    if (P.length) fg.computeVertexNormals();
    this.fieldMesh = new THREE.Mesh(fg, new THREE.MeshStandardMaterial({
      vertexColors: true, roughness: 0.75, metalness: 0, side: THREE.DoubleSide,
      // In front of the grey model drawn at the same place.
      polygonOffset: true, polygonOffsetFactor: -1, polygonOffsetUnits: -1,
    }));
    this.fieldMesh.name = 'geodesic-field';
    this.fieldMesh.frustumCulled = false;

    // The skeleton tree: nodes, edges, the current node.
    const nodeColor = nodeColors(layers, Math.max(this.layerCount, 1));
    const ng = new THREE.BufferGeometry();
    ng.setAttribute('position', new THREE.BufferAttribute(nodeP, 3));
    ng.setAttribute('color', new THREE.BufferAttribute(nodeColor, 3, true));
    this.nodeIndex = new THREE.BufferAttribute(new Uint32Array(Math.max(this.nodeCount, 1)), 1);
    this.nodeIndex.setUsage(THREE.DynamicDrawUsage);
    ng.setIndex(this.nodeIndex);
    const overlay = { depthTest: false, depthWrite: false, transparent: true };
    this.nodePoints = new THREE.Points(ng, new THREE.PointsMaterial({ ...overlay, size: 6, sizeAttenuation: false, vertexColors: true }));
    this.nodePoints.name = 'tree-nodes';
    const lines = (positions, count, color, opacity, name) => {
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
      const index = new THREE.BufferAttribute(new Uint32Array(Math.max(2 * count, 2)), 1);
      index.setUsage(THREE.DynamicDrawUsage);
      geometry.setIndex(index);
      const l = new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ ...overlay, color, opacity }));
      l.name = name;
      return [l, index];
    };
    [this.edgeLines, this.edgeIndex] = lines(pairSegments(nodeP, edges), this.edgeCount, TREE_EDGE_COLOR, 0.8, 'tree-edges');
    this.moves = airMoves(nodeP, edges, sequence);
    [this.airLines, this.airIndex] = lines(pairSegments(nodeP, this.moves.pairs), this.moves.count, AIR_MOVE_COLOR, 0.95, 'air-moves');
    // The skipped tool path: its own segment pairs, those of the layer range drawn.
    const skipped = preview.skippedSegments instanceof Float32Array ? preview.skippedSegments : empty(Float32Array);
    this.skippedCount = Math.floor(skipped.length / 6);
    const skippedLayers = preview.skippedLayers instanceof Uint32Array ? preview.skippedLayers : empty(Uint32Array);
    if (skippedLayers.length !== this.skippedCount) {
      throw new Error(`geodesic view: ${skippedLayers.length} skipped-segment layers for ${this.skippedCount} skipped segments`);
    }
    this.skippedLayers = skippedLayers;
    [this.skippedLines, this.skippedIndex] = lines(skipped.subarray(0, 6 * this.skippedCount), this.skippedCount, SKIPPED_COLOR, 1, 'skipped-path');
    const cg = new THREE.BufferGeometry();
    this.currentPosition = new THREE.BufferAttribute(new Float32Array(3), 3);
    cg.setAttribute('position', this.currentPosition);
    this.currentPoint = new THREE.Points(cg, new THREE.PointsMaterial({ ...overlay, size: 12, sizeAttenuation: false, color: CURRENT_NODE_COLOR }));
    this.currentPoint.name = 'tree-current-node';
    for (const o of [this.fieldMesh, this.edgeLines, this.airLines, this.skippedLines, this.nodePoints, this.currentPoint]) {
      o.frustumCulled = false;
      this.object.add(o);
    }
    // Overlays last, nodes over lines, the current node on top.
    this.edgeLines.renderOrder = 10;
    this.airLines.renderOrder = 11;
    this.skippedLines.renderOrder = 11;
    this.nodePoints.renderOrder = 12;
    this.currentPoint.renderOrder = 13;

    this.show = { field: true, tree: true, air: true, skipped: true };
    this.range = [0, Math.max(this.layerCount - 1, 0)];
    this.step = Math.max(this.nodeCount - 1, 0);
    this.selection = null;
    this.update();
  }

  /** The distance the field is drawn up to for layer l: its iso-value (all beyond the last). */
  isoValueOf(l) {
    if (l >= this.layerCount - 1 || !Number.isFinite(this.isoValues[l])) return Infinity;
    return this.isoValues[l];
  }

  /** Show layers lo..hi (clamped): the field up to layer hi's iso-value, the tree within lo..hi. */
  setLayerRange(lo, hi) {
    const last = Math.max(this.layerCount - 1, 0);
    const a = Math.min(Math.max(0, Math.floor(Number(lo) || 0)), last);
    const b = Math.min(Math.max(a, Math.floor(Number(hi) || 0)), last);
    this.range = [a, b];
    this.update();
    return this.range;
  }

  /** Show the tree as printed up to sequence position `step` (clamped to 0..N-1). */
  setStep(step) {
    const last = Math.max(this.nodeCount - 1, 0);
    this.step = Math.min(Math.max(0, Math.floor(Number(step) || 0)), last);
    this.update();
    return this.step;
  }

  setVisible(kind, visible) {
    if (!(kind in this.show)) throw new Error(`geodesic view: no layer '${kind}' (field, tree, air, skipped)`);
    this.show[kind] = !!visible;
    this.update();
  }

  /** Redraw the ranges and index lists for the current range, step and toggles. */
  update() {
    const [lo, hi] = this.range;
    const fieldCount = fieldTrianglesUpTo(this.fieldMaxValues, this.isoValueOf(hi));
    this.fieldMesh.geometry.setDrawRange(0, 3 * fieldCount);
    this.fieldMesh.visible = this.show.field && fieldCount > 0;
    const s = selectTree({ nodeLayers: this.nodeLayers, rank: this.rank, treeEdges: this.treeEdges, movePairs: this.moves.pairs },
      { lo, hi, step: this.step });
    this.selection = s;
    this.nodeIndex.array.set(s.nodes);
    this.nodeIndex.needsUpdate = true;
    this.nodePoints.geometry.setDrawRange(0, s.nodes.length);
    const fill = (index, picked, geometry) => {
      for (let k = 0; k < picked.length; k++) {
        index.array[2 * k] = 2 * picked[k];
        index.array[2 * k + 1] = 2 * picked[k] + 1;
      }
      index.needsUpdate = true;
      geometry.setDrawRange(0, 2 * picked.length);
    };
    fill(this.edgeIndex, s.edges, this.edgeLines.geometry);
    fill(this.airIndex, s.moves, this.airLines.geometry);
    this.nodePoints.visible = this.show.tree && s.nodes.length > 0;
    this.edgeLines.visible = this.show.tree && s.edges.length > 0;
    this.airLines.visible = this.show.air && s.moves.length > 0;
    let shownSkipped = 0;
    for (let k = 0; k < this.skippedCount; k++) {
      if (this.skippedLayers[k] < lo || this.skippedLayers[k] > hi) continue;
      this.skippedIndex.array[2 * shownSkipped] = 2 * k;
      this.skippedIndex.array[2 * shownSkipped + 1] = 2 * k + 1;
      shownSkipped++;
    }
    this.skippedIndex.needsUpdate = true;
    this.skippedLines.geometry.setDrawRange(0, 2 * shownSkipped);
    this.skippedShown = shownSkipped;
    this.skippedLines.visible = this.show.skipped && shownSkipped > 0;
    const c = s.current;
    const shownCurrent = c >= 0 && this.show.tree && this.nodeLayers[c] >= lo && this.nodeLayers[c] <= hi && this.step < this.nodeCount - 1;
    if (c >= 0) {
      const p = this.nodePoints.geometry.getAttribute('position').array;
      this.currentPosition.array.set([p[3 * c], p[3 * c + 1], p[3 * c + 2]]);
      this.currentPosition.needsUpdate = true;
    }
    this.currentPoint.visible = shownCurrent;
  }

  /** The node printed at the current step: {node, layer, step} or null without nodes. */
  currentNode() {
    const c = this.selection ? this.selection.current : -1;
    return c >= 0 ? { node: c, layer: this.nodeLayers[c], step: this.step } : null;
  }

  /** What is drawn now (for tests and the status line). */
  stats() {
    const s = this.selection;
    const drawnMoves = this.airLines.visible ? s.moves.length : 0;
    let drawnAirMm = 0;
    if (this.airLines.visible) for (const k of s.moves) drawnAirMm += this.moves.lengths[k];
    return {
      layers: this.layerCount,
      range: this.range.slice(),
      step: this.step,
      fieldTriangles: this.fieldTriangleCount,
      fieldDrawn: this.fieldMesh.visible ? this.fieldMesh.geometry.drawRange.count / 3 : 0,
      fieldMin: this.fieldMin,
      fieldMax: this.fieldMax,
      nodes: this.nodeCount,
      nodesDrawn: this.nodePoints.visible ? s.nodes.length : 0,
      edges: this.edgeCount,
      edgesDrawn: this.edgeLines.visible ? s.edges.length : 0,
      airMoves: this.moves.count,
      airMoveMm: this.moves.lengthMm,
      airDrawn: drawnMoves,
      airDrawnMm: drawnAirMm,
      skipped: this.skippedCount,
      skippedDrawn: this.skippedLines.visible ? this.skippedShown : 0,
      current: this.currentNode(),
      show: { ...this.show },
    };
  }

  /** Free the GPU buffers of every object (the view is not used after this). */
  dispose() {
    disposeTree(this.object);
  }
}
