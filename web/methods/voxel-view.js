// SPDX-License-Identifier: MIT
// Three.js objects of the voxel method's result (built from the preview buffers of a slice):
//   - the curved layer surfaces coloured by layer index: layers lo..hi-1 drawn in their colours,
//     layer hi (the slider's) highlighted; two meshes sharing one de-indexed, layer-sorted buffer,
//     each a contiguous draw range;
//   - missed voxels as red instanced cubes of the voxel width, support cells as grey ones;
//   - nozzle orientation glyphs: short lines along the nozzle axis at a decimated subset of the
//     printing segment ends, filtered by the same layer range as the tool-paths.
// The data preparation is in voxel-data.js (pure, unit-tested).
import * as THREE from 'three';
import { buildSurfaceArrays, CURRENT_LAYER_COLOR, decimateGlyphs, glyphRange, surfaceRanges } from './voxel-data.js';

/** Instanced cubes of size `width` at the centres (#N*3). */
function cubes(centres, width, color, opacity, name) {
  const N = centres.length / 3;
  const geometry = new THREE.BoxGeometry(width, width, width);
  const material = new THREE.MeshStandardMaterial({ color, roughness: 0.7, metalness: 0, transparent: opacity < 1, opacity });
  const mesh = new THREE.InstancedMesh(geometry, material, Math.max(N, 1));
  const m = mesh.instanceMatrix.array;
  for (let i = 0; i < N; i++) {
    const o = 16 * i;
    m[o] = m[o + 5] = m[o + 10] = m[o + 15] = 1;
    m[o + 12] = centres[3 * i];
    m[o + 13] = centres[3 * i + 1];
    m[o + 14] = centres[3 * i + 2];
  }
  mesh.count = N;
  mesh.instanceMatrix.needsUpdate = true;
  mesh.frustumCulled = false;
  mesh.name = name;
  return mesh;
}

/**
 * True when the preview carries curved-layer or voxel buffers (layer surfaces, missed or support
 * cells); nozzle axes alone (any method fills them) do not make a voxel view.
 */
export function hasVoxelBuffers(preview) {
  if (!preview) return false;
  return (preview.surfaceLayers && preview.surfaceLayers.length > 0)
    || (preview.missedVoxels && preview.missedVoxels.length > 0)
    || (preview.supportVoxels && preview.supportVoxels.length > 0)
    || false;
}

export class VoxelView {
  /**
   * Build the view of a slice's preview buffers (see core/pipeline/preview.h, flattened by wasm/helpers.cpp).
   * @param {object} preview positions, features, layers, axes, surfacePositions, surfaceTriangles,
   *   surfaceLayers, missedVoxels, supportVoxels, voxelWidth
   * @param {{maxGlyphs?: number, glyphLength?: number}} [options]
   */
  static async build(preview, { maxGlyphs = 2000, glyphLength, budgetMs, block } = {}) {
    const surfaces = await buildSurfaceArrays(preview, { budgetMs, block });
    const width = Number(preview.voxelWidth) > 0 ? Number(preview.voxelWidth) : 0;
    const glyphs = await decimateGlyphs(preview, { maxGlyphs, length: glyphLength || Math.max(2.5 * width, 1.5), budgetMs });
    return new VoxelView(preview, surfaces, glyphs, width);
  }

  /** Use VoxelView.build(). */
  constructor(preview, surfaces, glyphs, width) {
    this.object = new THREE.Group();
    this.object.name = 'voxel-view';
    this.surfaceLayerCount = surfaces.layerCount;
    this.surfaceTriangles = surfaces.triangleCount;
    this.surfaceStarts = surfaces.starts;
    this.voxelWidth = width;

    // Layer surfaces: one position buffer, two meshes (earlier layers, current layer).
    const geometry = (colors) => {
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', this.surfacePosition);
      if (colors) g.setAttribute('color', colors);
      return g;
    };
    this.surfacePosition = new THREE.BufferAttribute(surfaces.positions, 3);
    const colors = new THREE.BufferAttribute(surfaces.colors, 3, true);
    const common = { side: THREE.DoubleSide, flatShading: true, roughness: 0.8, metalness: 0, polygonOffset: true, polygonOffsetFactor: 2, polygonOffsetUnits: 2 };
    this.belowMesh = new THREE.Mesh(geometry(colors), new THREE.MeshStandardMaterial({ ...common, vertexColors: true }));
    this.belowMesh.name = 'layer-surfaces';
    const [r, gr, b] = CURRENT_LAYER_COLOR;
    this.currentMesh = new THREE.Mesh(geometry(null), new THREE.MeshStandardMaterial({
      ...common, color: new THREE.Color(r / 255, gr / 255, b / 255), emissive: new THREE.Color(0.35, 0.3, 0.08),
    }));
    this.currentMesh.name = 'layer-surface-current';
    for (const m of [this.belowMesh, this.currentMesh]) {
      m.frustumCulled = false;
      this.object.add(m);
    }

    // Missed voxels (red) and support cells (grey).
    const missed = preview.missedVoxels || new Float32Array(0);
    const support = preview.supportVoxels || new Float32Array(0);
    const cube = width > 0 ? width * 0.92 : 0.3;
    this.missedCount = missed.length / 3;
    this.supportCount = support.length / 3;
    this.missedMesh = cubes(missed, cube, 0xff3b30, 1, 'missed-voxels');
    this.supportMesh = cubes(support, cube, 0x9aa0a8, 0.55, 'support-voxels');
    this.missedMesh.visible = this.missedCount > 0;
    this.supportMesh.visible = false;
    this.object.add(this.missedMesh, this.supportMesh);

    // Nozzle-axis glyphs.
    this.glyphs = glyphs;
    const gg = new THREE.BufferGeometry();
    gg.setAttribute('position', new THREE.BufferAttribute(glyphs.positions, 3));
    this.glyphLines = new THREE.LineSegments(gg, new THREE.LineBasicMaterial({ color: 0xe6f0ff, transparent: true, opacity: 0.85 }));
    this.glyphLines.name = 'axis-glyphs';
    this.glyphLines.frustumCulled = false;
    this.glyphLines.visible = false;
    this.object.add(this.glyphLines);

    this.show = { surfaces: true, missed: true, support: false, glyphs: false };
    this.surfaceRange = [0, Math.max(this.surfaceLayerCount - 1, 0)];
    this.setSurfaceLayer(this.surfaceLayerCount - 1);
    this.setGlyphLayerRange(0, Number.MAX_SAFE_INTEGER);
  }

  /** Show the surfaces of layers lo..hi (default lo = 0), layer hi highlighted. */
  setSurfaceLayer(hi, lo = 0) {
    const r = surfaceRanges(this.surfaceStarts, lo, hi);
    this.surfaceRange = [r.lo, r.hi];
    this.belowMesh.geometry.setDrawRange(r.below.start * 3, r.below.count * 3);
    this.currentMesh.geometry.setDrawRange(r.current.start * 3, r.current.count * 3);
    this.belowMesh.visible = this.show.surfaces && r.below.count > 0;
    this.currentMesh.visible = this.show.surfaces && r.current.count > 0;
    return r;
  }

  /** Glyphs of the tool-path layers lo..hi. */
  setGlyphLayerRange(lo, hi) {
    const r = glyphRange(this.glyphs.starts, lo, hi);
    this.glyphLines.geometry.setDrawRange(r.start * 2, r.count * 2);
    return r;
  }

  setVisible(kind, visible) {
    this.show[kind] = !!visible;
    if (kind === 'surfaces') this.setSurfaceLayer(this.surfaceRange[1], this.surfaceRange[0]);
    if (kind === 'missed') this.missedMesh.visible = this.show.missed && this.missedCount > 0;
    if (kind === 'support') this.supportMesh.visible = this.show.support && this.supportCount > 0;
    if (kind === 'glyphs') this.glyphLines.visible = this.show.glyphs && this.glyphs.count > 0;
  }

  /** What is drawn now (for tests and the status line). */
  stats() {
    const tri = (m) => (m.visible ? m.geometry.drawRange.count / 3 : 0);
    return {
      surfaceLayers: this.surfaceLayerCount,
      surfaceTriangles: this.surfaceTriangles,
      drawnTriangles: tri(this.belowMesh) + tri(this.currentMesh),
      currentTriangles: tri(this.currentMesh),
      surfaceRange: this.surfaceRange.slice(),
      missed: this.missedCount,
      missedDrawn: this.missedMesh.visible ? this.missedMesh.count : 0,
      support: this.supportCount,
      supportDrawn: this.supportMesh.visible ? this.supportMesh.count : 0,
      glyphs: this.glyphs.count,
      glyphsDrawn: this.glyphLines.visible ? this.glyphLines.geometry.drawRange.count / 2 : 0,
      voxelWidth: this.voxelWidth,
    };
  }
}
