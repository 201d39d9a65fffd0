// SPDX-License-Identifier: MIT
// Three.js objects of the check before writing (issue 25 item 6): where the simulated program
// fails, as two point clouds over the part, tips of the unsupported samples (printed over air)
// and of the colliding ones (the nozzle cone in material printed before), each in its colour
// (check-data.js). They are drawn without depth test, so the points inside or behind the part show
// too: a few thousand at most, each a tinted disc in a dark ring that reads on any tool-path
// colour. The geodesic view draws the left-out tool path (skippedSegments) itself.
import * as THREE from 'three';
import { disposeTree } from '../viewer.js';
import { FAILING_POINTS, failingPoints, ringSprite } from './check-data.js';

const SPRITE_SIZE = 32;
/** Point size in pixels (not attenuated: legible at any zoom). */
export const POINT_SIZE = 8;

export class CheckView {
  /**
   * @param {object} preview unsupportedPoints, collisionPoints (Float32Array #N*3, part frame, mm)
   * @param {object} [verify] the report's verify section: the colliding samples' total (the
   *   preview holds a spread of at most 4000)
   * @throws Error for a buffer that is not whole xyz triples
   */
  constructor(preview, verify = null) {
    const points = failingPoints(preview);
    this.totals = { unsupported: NaN, collisions: verify && Number.isFinite(verify.collisions) ? verify.collisions : NaN };
    this.object = new THREE.Group();
    this.object.name = 'check-view';
    this.sprite = new THREE.DataTexture(ringSprite(SPRITE_SIZE), SPRITE_SIZE, SPRITE_SIZE);
    this.sprite.magFilter = THREE.LinearFilter;
    this.sprite.minFilter = THREE.LinearFilter;
    // Its pixels are display values, like the colours below (the legend's CSS colours).
    this.sprite.colorSpace = THREE.SRGBColorSpace;
    this.sprite.needsUpdate = true;
    this.clouds = {};
    this.counts = {};
    for (const f of FAILING_POINTS) {
      const { positions, count } = points[f.kind];
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
      const material = new THREE.PointsMaterial({
        size: POINT_SIZE, sizeAttenuation: false, map: this.sprite, alphaTest: 0.5,
        color: new THREE.Color().setRGB(...f.color.map((x) => x / 255), THREE.SRGBColorSpace),
        // In the transparent pass, which comes after the opaque one: the layer surfaces (transparent)
        // would otherwise be blended over the points.
        depthTest: false, depthWrite: false, transparent: true,
      });
      const cloud = new THREE.Points(geometry, material);
      cloud.name = `check-${f.kind}`;
      cloud.frustumCulled = false;
      // Over the tool paths and the geodesic overlays (render orders up to 13).
      cloud.renderOrder = 14;
      this.object.add(cloud);
      this.clouds[f.kind] = cloud;
      this.counts[f.kind] = count;
    }
    this.visible = true;
    this.update();
  }

  /** Show or hide both clouds. */
  setVisible(visible) {
    this.visible = !!visible;
    this.update();
  }

  update() {
    for (const [kind, cloud] of Object.entries(this.clouds)) cloud.visible = this.visible && this.counts[kind] > 0;
  }

  /** What is held and drawn (for the legend and the tests). */
  stats() {
    const drawn = (kind) => (this.clouds[kind].visible ? this.counts[kind] : 0);
    return {
      unsupported: this.counts.unsupported,
      collisions: this.counts.collisions,
      collisionsTotal: this.totals.collisions,
      unsupportedDrawn: drawn('unsupported'),
      collisionsDrawn: drawn('collisions'),
      visible: this.visible,
    };
  }

  /** Free the GPU buffers and the sprite (the view is not used after this). */
  dispose() {
    disposeTree(this.object);
    this.sprite.dispose();
  }
}
