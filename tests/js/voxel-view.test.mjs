// SPDX-License-Identifier: MIT
// The voxel view's three.js objects (web/methods/voxel-view.js) in Node: the surface meshes draw exactly
// the triangles of layers <= the slider's (the current layer in its own mesh), missed and support
// cells are instanced cubes of the voxel width at the given centres, glyphs follow the layer
// range and the toggles; a planar preview (no voxel buffers) makes no voxel view.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import * as THREE from 'three';
import { VoxelView, hasVoxelBuffers } from '../../web/methods/voxel-view.js';

// Two stacked quads per layer (4 vertices, 2 triangles each), L layers; a zig-zag tool-path.
function makePreview(L) {
  const surfacePositions = [];
  const surfaceTriangles = [];
  const surfaceLayers = [];
  for (let l = 0; l < L; l++) {
    const z = 0.3 * l;
    const v = surfacePositions.length / 3;
    surfacePositions.push(0, 0, z, 10, 0, z, 10, 10, z, 0, 10, z);
    surfaceTriangles.push(v, v + 1, v + 2, v, v + 2, v + 3);
    surfaceLayers.push(l, l);
  }
  const positions = [];
  const features = [];
  const layers = [];
  const axes = [];
  for (let l = 0; l < L; l++) {
    for (let i = 0; i < 20; i++) {
      positions.push(i * 0.5, 0, 0.3 * l, (i + 1) * 0.5, 0, 0.3 * l);
      features.push(i === 0 ? 0 : 4);
      layers.push(l);
      axes.push(0, 0, 1);
    }
  }
  return {
    positions: new Float32Array(positions),
    features: new Uint8Array(features),
    layers: new Uint32Array(layers),
    machine: new Float32Array(features.length * 6),
    axes: new Float32Array(axes),
    surfacePositions: new Float32Array(surfacePositions),
    surfaceTriangles: new Uint32Array(surfaceTriangles),
    surfaceLayers: new Uint32Array(surfaceLayers),
    missedVoxels: new Float32Array([1, 2, 3, 4, 5, 6]),
    supportVoxels: new Float32Array([7, 8, 0.2]),
    voxelWidth: 0.4,
  };
}

test('VoxelView: the surface slider shows layers <= it, the current one highlighted', async () => {
  const p = makePreview(12);
  assert.equal(hasVoxelBuffers(p), true);
  const v = await VoxelView.build(p, { maxGlyphs: 50 });
  let s = v.stats();
  assert.equal(s.surfaceLayers, 12);
  assert.equal(s.surfaceTriangles, 24);
  assert.equal(s.drawnTriangles, 24, 'all layers at first');
  assert.equal(s.currentTriangles, 2);
  for (const hi of [0, 3, 11]) {
    v.setSurfaceLayer(hi);
    s = v.stats();
    assert.equal(s.drawnTriangles, 2 * (hi + 1), `layers 0..${hi}`);
    // The current mesh's range holds the triangles of layer hi (z = 0.3 hi).
    const { start, count } = v.currentMesh.geometry.drawRange;
    const pos = v.currentMesh.geometry.getAttribute('position').array;
    for (let k = start; k < start + count; k++) assert.ok(Math.abs(pos[3 * k + 2] - 0.3 * hi) < 1e-6);
    const below = v.belowMesh.geometry.drawRange;
    for (let k = below.start; k < below.start + below.count; k++) assert.ok(pos[3 * k + 2] < 0.3 * hi - 1e-6);
  }
  v.setVisible('surfaces', false);
  assert.equal(v.stats().drawnTriangles, 0);
  v.setVisible('surfaces', true);
  assert.equal(v.stats().drawnTriangles, 24);
});

test('VoxelView: missed and support cells are cubes of the voxel width at the centres; glyphs follow the range', async () => {
  const p = makePreview(6);
  const v = await VoxelView.build(p, { maxGlyphs: 1000 });
  const s = v.stats();
  assert.equal(s.missed, 2);
  assert.equal(s.missedDrawn, 2, 'missed shown by default');
  assert.equal(s.support, 1);
  assert.equal(s.supportDrawn, 0, 'support hidden by default');
  v.setVisible('support', true);
  assert.equal(v.stats().supportDrawn, 1);
  const m = new THREE.Matrix4();
  v.missedMesh.getMatrixAt(1, m);
  assert.deepEqual(new THREE.Vector3().setFromMatrixPosition(m).toArray(), [4, 5, 6]);
  v.missedMesh.geometry.computeBoundingBox();
  const size = v.missedMesh.geometry.boundingBox.getSize(new THREE.Vector3());
  assert.ok(Math.abs(size.x - 0.4 * 0.92) < 1e-6, `cube size ${size.x}`);
  // Glyphs: every printing segment (spacing below a segment's length), hidden until toggled.
  assert.equal(s.glyphs, 6 * 19);
  assert.equal(s.glyphsDrawn, 0);
  v.setVisible('glyphs', true);
  assert.equal(v.stats().glyphsDrawn, 6 * 19);
  v.setGlyphLayerRange(2, 3);
  assert.equal(v.stats().glyphsDrawn, 2 * 19);
});

test('a planar preview (nozzle axes, no surfaces or cells) makes no voxel view', () => {
  const p = makePreview(3);
  const planar = { positions: p.positions, features: p.features, layers: p.layers, machine: p.machine,
    axes: p.axes, surfacePositions: new Float32Array(0), surfaceTriangles: new Uint32Array(0),
    surfaceLayers: new Uint32Array(0), missedVoxels: new Float32Array(0), supportVoxels: new Float32Array(0), voxelWidth: 0 };
  assert.equal(hasVoxelBuffers(planar), false);
  assert.equal(hasVoxelBuffers({ positions: p.positions, features: p.features, layers: p.layers }), false);
  assert.equal(hasVoxelBuffers(null), false);
});
