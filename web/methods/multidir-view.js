// SPDX-License-Identifier: MIT
// Three.js objects of the multi-directional method's result (paper 000), built from the preview
// buffers:
//   - the parts' closed meshes, each in its own colour, sorted by print index so the order slider
//     ("parts 0..k printed") is one draw range;
//   - an arrow per part: its print direction from its surface centroid, in the part's colour,
//     drawn over the model (no depth test) for the parts shown;
//   - the risky faces of the placed part (the grey model): before (along +Z) or after (in the part
//     each face ends up in), as a red overlay.
// The data preparation is in multidir-data.js (pure, unit-tested).
import * as THREE from 'three';
import { disposeTree } from '../viewer.js';
import {
  arrowSegments, checkMultidirBuffers, flaggedArea, flaggedTriangles, partCentroids, partColor, partDirections, sortPartTriangles,
} from './multidir-data.js';

/** Colour of the risky-face overlay; opacity of the parts. */
export const RISKY_COLOR = 0xff2b2b;
export const PART_OPACITY = 0.55;

export class MultidirView {
  /**
   * @param {object} preview partPositions, partTriangles, partIds, riskyBefore, riskyAfter
   * @param {object} [multidir] report.multidir (parts[].direction, part_count)
   * @param {{positions: Float32Array, indices: Uint32Array}} [mesh] the placed part (the risky
   *   flags are per triangle of it)
   * @throws Error when the buffers disagree (multidir-data.js checkMultidirBuffers)
   */
  constructor(preview, multidir = null, mesh = null) {
    const meshTriangles = mesh && mesh.indices ? mesh.indices.length / 3 : null;
    const check = checkMultidirBuffers(preview, meshTriangles);
    const m = multidir && typeof multidir === 'object' ? multidir : {};
    this.partCount = Math.max(check.parts, Number.isInteger(m.part_count) ? m.part_count : 0);
    this.triangleCount = check.triangles;

    this.object = new THREE.Group();
    this.object.name = 'multidir-view';

    // Parts, sorted by print index.
    const sorted = sortPartTriangles(preview, this.partCount);
    this.starts = sorted.starts;
    const pg = new THREE.BufferGeometry();
    pg.setAttribute('position', new THREE.BufferAttribute(sorted.positions, 3));
    pg.setAttribute('color', new THREE.BufferAttribute(sorted.colors, 3, true));
    if (sorted.positions.length) pg.computeVertexNormals();
    this.partMesh = new THREE.Mesh(pg, new THREE.MeshStandardMaterial({
      vertexColors: true, roughness: 0.7, metalness: 0, side: THREE.DoubleSide,
      // See-through, so the tool-paths and arrows inside the parts stay visible.
      transparent: true, opacity: PART_OPACITY, depthWrite: false,
      polygonOffset: true, polygonOffsetFactor: -1, polygonOffsetUnits: -1,
    }));
    this.partMesh.name = 'multidir-parts';

    // Arrows: 3 segments per part, coloured like the part, length from the parts' extent.
    const centroids = partCentroids(preview, this.partCount);
    const directions = partDirections(m, this.partCount);
    this.centroids = centroids;
    this.directions = directions;
    pg.computeBoundingBox();
    const box = pg.boundingBox;
    const size = box && !box.isEmpty() ? box.getSize(new THREE.Vector3()).length() : 10;
    this.arrowLength = Math.max(0.25 * size, 1);
    const segs = arrowSegments(centroids, directions, this.arrowLength);
    const colors = new Uint8Array(segs.length);
    for (let i = 0; i < this.partCount; i++) {
      const c = partColor(i);
      for (let v = 0; v < 6; v++) colors.set(c, 18 * i + 3 * v);
    }
    const ag = new THREE.BufferGeometry();
    ag.setAttribute('position', new THREE.BufferAttribute(segs, 3));
    ag.setAttribute('color', new THREE.BufferAttribute(colors, 3, true));
    this.arrows = new THREE.LineSegments(ag, new THREE.LineBasicMaterial({ vertexColors: true, depthTest: false, depthWrite: false, transparent: true }));
    this.arrows.name = 'multidir-arrows';
    this.arrows.renderOrder = 10;

    // Risky faces of the placed part, before and after.
    this.riskyArea = { before: 0, after: 0 };
    this.riskyCount = { before: 0, after: 0 };
    this.riskyMeshes = {};
    for (const kind of ['before', 'after']) {
      const flags = kind === 'before' ? preview.riskyBefore : preview.riskyAfter;
      const rg = new THREE.BufferGeometry();
      let index = new Uint32Array(0);
      if (mesh && flags && flags.length) {
        index = flaggedTriangles(mesh.indices, flags);
        this.riskyArea[kind] = flaggedArea(mesh.positions, mesh.indices, flags);
        rg.setAttribute('position', new THREE.BufferAttribute(mesh.positions, 3));
      } else {
        rg.setAttribute('position', new THREE.BufferAttribute(new Float32Array(0), 3));
      }
      rg.setIndex(new THREE.BufferAttribute(index, 1));
      this.riskyCount[kind] = index.length / 3;
      const r = new THREE.Mesh(rg, new THREE.MeshBasicMaterial({
        color: RISKY_COLOR, side: THREE.DoubleSide, transparent: true, opacity: 0.85,
        polygonOffset: true, polygonOffsetFactor: -2, polygonOffsetUnits: -2,
      }));
      r.name = `multidir-risky-${kind}`;
      this.riskyMeshes[kind] = r;
    }
    for (const o of [this.partMesh, this.arrows, this.riskyMeshes.before, this.riskyMeshes.after]) {
      o.frustumCulled = false;
      this.object.add(o);
    }
    this.show = { parts: true, arrows: true };
    this.risky = 'none';
    this.order = Math.max(this.partCount - 1, 0);
    this.update();
  }

  /** Show parts 0..k in print order (clamped to 0..parts-1). */
  setOrder(k) {
    const last = Math.max(this.partCount - 1, 0);
    this.order = Math.min(Math.max(0, Math.floor(Number(k) || 0)), last);
    this.update();
    return this.order;
  }

  /** Highlight the risky faces: 'none' | 'before' | 'after'. */
  setRisky(kind) {
    if (!['none', 'before', 'after'].includes(kind)) throw new Error(`multidir view: risky '${kind}' (none, before, after)`);
    this.risky = kind;
    this.update();
  }

  setVisible(kind, visible) {
    if (!(kind in this.show)) throw new Error(`multidir view: no layer '${kind}' (parts, arrows)`);
    this.show[kind] = !!visible;
    this.update();
  }

  update() {
    const shown = this.partCount ? this.order + 1 : 0;
    const triangles = this.starts[Math.min(shown, this.partCount)] || 0;
    this.partMesh.geometry.setDrawRange(0, 3 * triangles);
    this.partMesh.visible = this.show.parts && triangles > 0;
    this.arrows.geometry.setDrawRange(0, 6 * shown);
    this.arrows.visible = this.show.arrows && shown > 0;
    this.riskyMeshes.before.visible = this.risky === 'before' && this.riskyCount.before > 0;
    this.riskyMeshes.after.visible = this.risky === 'after' && this.riskyCount.after > 0;
  }

  /** What is drawn now (for tests and the status line). */
  stats() {
    const shown = this.partCount ? this.order + 1 : 0;
    return {
      parts: this.partCount,
      order: this.order,
      partsShown: this.partMesh.visible ? shown : 0,
      trianglesDrawn: this.partMesh.visible ? this.partMesh.geometry.drawRange.count / 3 : 0,
      triangles: this.triangleCount,
      arrowsDrawn: this.arrows.visible ? shown : 0,
      risky: this.risky,
      riskyDrawn: this.risky === 'none' ? 0 : (this.riskyMeshes[this.risky].visible ? this.riskyCount[this.risky] : 0),
      riskyTriangles: { ...this.riskyCount },
      riskyAreaMm2: { ...this.riskyArea },
      show: { ...this.show },
    };
  }

  /** Free the GPU buffers (the view is not used after this). */
  dispose() {
    disposeTree(this.object);
  }
}
