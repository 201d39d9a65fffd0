// SPDX-License-Identifier: MIT
// Machine animation: a simple articulated model of the selected machine moving the part through
// the program, driven by the slice result's preview.machine (6 machine values per move end).
//   cartesian3: the bed and a nozzle carriage on an X rail;
//   rotary4:    a platform turning about the X axis through the pivot (A);
//   table5:     a trunnion tilting about Y through the pivot (B) carrying a rotary platform (C);
//   robot6:     the six links drawn between the DH frame origins, the platform on the flange
//               (flange_to_platform), the fixed nozzle.
// The part mesh and the material deposited so far ride on the platform (their coordinates are part
// frame; the platform's matrix is the core's pose of the move, preview.poses: quaternion and
// translation per segment, built with GLM in core/pipeline/preview.cpp; for a preview without
// poses, the forward map's platform transform of web/machine-kinematics.js).
// setStep(s) poses everything for move s and measures the tip error in the scene itself: the
// distance between the platform's world matrix applied to the move's part-frame end point and the
// nozzle tip object's world position (0 when the nozzle sits on the deposition point).
import * as THREE from 'three';
import { FEATURES } from './preview.js';
import {
  dhFrames, dhTable, machineAxisNames, machineKind, nozzleAxisMachine, nozzleTip, origin4,
  platformTransform, trunnionTransform,
} from './machine-kinematics.js';

const UP = new THREE.Vector3(0, 1, 0);
const ONE = new THREE.Vector3(1, 1, 1);

/** THREE.Matrix4 from a row-major array of 16. */
function matrixOf(m) {
  return new THREE.Matrix4().set(...m);
}

function material(color, extra = {}) {
  return new THREE.MeshStandardMaterial({ color, roughness: 0.6, metalness: 0.15, ...extra });
}

export class MachineView {
  /**
   * @param {object} profile the machine JSON object (report.machine_profile)
   * @param {{positions: Float32Array, features: Uint8Array, machine: Float32Array, poses?: Float32Array}} preview
   *   #S*6 part-frame segment end points, #S feature codes, #S*6 machine values, #S*7 platform
   *   poses (quaternion x y z w, translation; optional: the forward map gives them otherwise)
   * @param {{positions: Float32Array, indices: Uint32Array}} [mesh] the placed part (part frame)
   * @throws RangeError for an unknown kind or buffers that disagree
   */
  constructor(profile, preview, mesh) {
    this.kind = machineKind(profile);
    if (!this.kind) throw new RangeError(`unknown machine kind ${profile && profile.kind}`);
    const S = preview.features.length;
    if (preview.positions.length !== 6 * S || !preview.machine || preview.machine.length !== 6 * S) {
      throw new RangeError(`machine preview disagrees: ${S} segments, ${preview.positions.length / 6} positions, ` +
        `${preview.machine ? preview.machine.length / 6 : 0} machine value rows`);
    }
    this.profile = profile;
    this.preview = preview;
    this.posesFromCore = !!preview.poses && preview.poses.length === 7 * S && S > 0;
    this.stepCount = S;
    this.step = -1;
    this.tipError = NaN;
    this.axisNames = machineAxisNames(this.kind);
    this.object = new THREE.Group();
    this.object.name = 'machine';
    this.disposables = [];

    this.partBox = new THREE.Box3();
    this.platform = this.#fixed(new THREE.Group(), 'platform');
    this.object.add(this.platform);
    this.#buildPart(mesh);
    this.#buildDeposit();
    this.#buildPlatformPlate();
    this.#buildNozzle();
    if (this.kind === 'robot6') this.#buildRobot();
    else this.#buildGantry();
    if (S > 0) this.setStep(0);
  }

  // A group whose matrix is set directly (no position/quaternion decomposition).
  #fixed(object, name) {
    object.name = name;
    object.matrixAutoUpdate = false;
    return object;
  }

  #geometry(g) {
    this.disposables.push(g);
    return g;
  }

  #material(m) {
    this.disposables.push(m);
    return m;
  }

  #buildPart(mesh) {
    if (mesh && mesh.positions && mesh.positions.length) {
      const g = this.#geometry(new THREE.BufferGeometry());
      g.setAttribute('position', new THREE.BufferAttribute(mesh.positions, 3));
      if (mesh.indices && mesh.indices.length) g.setIndex(new THREE.BufferAttribute(mesh.indices, 1));
      g.computeBoundingBox();
      this.partBox.copy(g.boundingBox);
      const m = this.#material(new THREE.MeshStandardMaterial({
        color: 0x8fb3d9, roughness: 0.65, flatShading: true, side: THREE.DoubleSide,
        transparent: true, opacity: 0.2, depthWrite: false,
      }));
      const part = new THREE.Mesh(g, m);
      part.name = 'machine-part';
      this.platform.add(part);
    }
    if (this.partBox.isEmpty()) {
      const p = this.preview.positions;
      for (let i = 0; i < p.length; i += 3) this.partBox.expandByPoint(new THREE.Vector3(p[i], p[i + 1], p[i + 2]));
    }
    if (this.partBox.isEmpty()) this.partBox.set(new THREE.Vector3(-10, -10, 0), new THREE.Vector3(10, 10, 10));
  }

  // Extruding segments in move order (an index into the preview's vertices) with per-move prefix
  // counts, so "deposited so far" at move s is one drawRange.
  #buildDeposit() {
    const { positions, features } = this.preview;
    const S = this.stepCount;
    const before = new Uint32Array(S + 1);
    let n = 0;
    for (let s = 0; s < S; s++) {
      before[s] = n;
      if (features[s] !== 0) n++;
    }
    before[S] = n;
    const index = new Uint32Array(2 * n);
    const colors = new Uint8Array(6 * S);
    for (let s = 0, k = 0; s < S; s++) {
      const c = (FEATURES[features[s]] || FEATURES[0]).color;
      colors.set(c, 6 * s);
      colors.set(c, 6 * s + 3);
      if (features[s] !== 0) {
        index[2 * k] = 2 * s;
        index[2 * k + 1] = 2 * s + 1;
        k++;
      }
    }
    this.depositedBefore = before;
    const g = this.#geometry(new THREE.BufferGeometry());
    g.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    g.setAttribute('color', new THREE.BufferAttribute(colors, 3, true));
    g.setIndex(new THREE.BufferAttribute(index, 1));
    const lines = new THREE.LineSegments(g, this.#material(new THREE.LineBasicMaterial({ vertexColors: true })));
    lines.name = 'machine-deposit';
    lines.frustumCulled = false;
    this.deposit = lines;
    this.platform.add(lines);
    // The current deposition point (part frame), a small marker.
    const dot = new THREE.Mesh(this.#geometry(new THREE.SphereGeometry(0.6, 12, 8)),
      this.#material(new THREE.MeshBasicMaterial({ color: 0xff3b30 })));
    dot.name = 'machine-point';
    this.point = dot;
    this.platform.add(dot);
  }

  #buildPlatformPlate() {
    const b = this.partBox;
    const margin = 10;
    const sx = Math.max(b.max.x - b.min.x + 2 * margin, 40);
    const sy = Math.max(b.max.y - b.min.y + 2 * margin, 40);
    const cx = (b.max.x + b.min.x) / 2;
    const cy = (b.max.y + b.min.y) / 2;
    const round = this.kind === 'table5' || this.kind === 'robot6';
    const g = round
      ? new THREE.CylinderGeometry(Math.hypot(sx, sy) / 2, Math.hypot(sx, sy) / 2, 3, 48).rotateX(Math.PI / 2)
      : new THREE.BoxGeometry(sx, sy, 3);
    g.translate(round ? 0 : cx, round ? 0 : cy, -1.55);
    const plate = new THREE.Mesh(this.#geometry(g), this.#material(material(0x3a4656)));
    plate.name = 'machine-platform-plate';
    this.platform.add(plate);
    this.plateRadius = Math.hypot(sx, sy) / 2;
  }

  #buildNozzle() {
    const nozzle = (this.profile && this.profile.nozzle) || {};
    const half = THREE.MathUtils.degToRad(Number(nozzle.cone_half_angle_deg) || 40);
    const length = Number(nozzle.cone_length) || 25;
    const size = nozzle.carriage_size;
    const carriage = Array.isArray(size) && size.length === 3 ? size.map(Number) : [60, 60, 40];
    const group = this.#fixed(new THREE.Group(), 'machine-nozzle');
    // Cone: apex at the tip (local origin), opening along local +Z (the nozzle axis).
    const cone = new THREE.ConeGeometry(length * Math.tan(half), length, 32, 1, false).rotateX(-Math.PI / 2).translate(0, 0, length / 2);
    group.add(new THREE.Mesh(this.#geometry(cone), this.#material(material(0xc9a227, { transparent: true, opacity: 0.6 }))));
    const box = new THREE.BoxGeometry(...carriage).translate(0, 0, length + carriage[2] / 2);
    group.add(new THREE.Mesh(this.#geometry(box), this.#material(material(0x59636e, { transparent: true, opacity: 0.55 }))));
    // The tip itself: an object at the local origin whose world position is the nozzle tip.
    this.tip = new THREE.Object3D();
    this.tip.name = 'machine-nozzle-tip';
    group.add(this.tip);
    this.nozzle = group;
    this.nozzleLength = length;
    this.carriage = carriage;
    this.object.add(group);
  }

  // Gantry machines: the linear axes move the nozzle; a rail shows X, the limits box the work area.
  #buildGantry() {
    const lim = (this.profile && this.profile.axis_limits) || {};
    const range = (axis, lo, hi) => (Array.isArray(lim[axis]) ? lim[axis].map(Number) : [lo, hi]);
    const [x0, x1] = range('X', this.partBox.min.x - 60, this.partBox.max.x + 60);
    const [y0, y1] = range('Y', this.partBox.min.y - 60, this.partBox.max.y + 60);
    this.xRange = [x0, x1];
    const rail = new THREE.BoxGeometry(1, 12, 12);
    this.rail = new THREE.Mesh(this.#geometry(rail), this.#material(material(0x7d8894)));
    this.rail.name = 'machine-x-rail';
    this.object.add(this.rail);
    // Work area outline at machine z = 0.
    const outline = new THREE.BufferGeometry().setFromPoints([
      [x0, y0], [x1, y0], [x1, y0], [x1, y1], [x1, y1], [x0, y1], [x0, y1], [x0, y0],
    ].map(([x, y]) => new THREE.Vector3(x, y, 0)));
    this.object.add(new THREE.LineSegments(this.#geometry(outline), this.#material(new THREE.LineBasicMaterial({ color: 0x56606d }))));
    const P = new THREE.Vector3(...(Array.isArray(this.profile.pivot) ? this.profile.pivot.map(Number) : [0, 0, 0]));
    const axisMaterial = this.#material(material(0xa0aab5));
    if (this.kind === 'rotary4') {
      // The A axle: along X through the pivot, the width of the platform plus bearings.
      const len = this.plateRadius * 2 + 40;
      const axle = new THREE.Mesh(this.#geometry(new THREE.CylinderGeometry(4, 4, len, 20).rotateZ(Math.PI / 2)), axisMaterial);
      axle.position.copy(P);
      this.object.add(axle);
      for (const side of [-1, 1]) {
        const bearing = new THREE.Mesh(this.#geometry(new THREE.BoxGeometry(10, 20, 20)), axisMaterial);
        bearing.position.set(P.x + side * (len / 2), P.y, P.z);
        this.object.add(bearing);
      }
    }
    if (this.kind === 'head5' || this.kind === 'head4') {
      // The head's arm from the carriage point (where B and C turn) to the top of the nozzle cone.
      this.unitCylinder = this.unitCylinder || this.#geometry(new THREE.CylinderGeometry(1, 1, 1, 20));
      this.headArm = new THREE.Mesh(this.unitCylinder, this.#material(material(0x6b5b95)));
      this.headArm.name = 'machine-head-arm';
      this.object.add(this.headArm);
    }
    if (this.kind === 'table5') {
      // The trunnion (B, about Y through the pivot): a cradle under the platform with two cheeks
      // at the ends of the tilt axis; it carries the C platform.
      const r = this.plateRadius;
      const cradle = this.#fixed(new THREE.Group(), 'machine-trunnion');
      const pivotZ = P.z;
      const floor = new THREE.BoxGeometry(2 * r + 10, 2 * r + 10, 6).translate(P.x, P.y, Math.min(-8, pivotZ - 8));
      cradle.add(new THREE.Mesh(this.#geometry(floor), this.#material(material(0x6b5b95))));
      for (const side of [-1, 1]) {
        const cheekTop = pivotZ + 10;
        const cheekBottom = Math.min(-11, pivotZ - 11);
        const cheek = new THREE.BoxGeometry(2 * r + 10, 8, cheekTop - cheekBottom)
          .translate(P.x, P.y + side * (r + 9), (cheekTop + cheekBottom) / 2);
        cradle.add(new THREE.Mesh(this.#geometry(cheek), this.#material(material(0x6b5b95))));
      }
      // The B axis: two stubs on the tilt axis outside the cheeks (the stand's bearings).
      for (const side of [-1, 1]) {
        const stub = new THREE.Mesh(this.#geometry(new THREE.CylinderGeometry(5, 5, 24, 20)), axisMaterial);
        stub.position.set(P.x, P.y + side * (r + 25), P.z);
        this.object.add(stub);
      }
      this.trunnion = cradle;
      this.object.add(cradle);
    }
  }

  // robot6: a base, joints as short cylinders along each DH frame's z axis, links along the DH
  // offsets (d along z, then a along x) between consecutive frame origins, and a flange disc.
  #buildRobot() {
    this.dh = dhTable(this.profile);
    const reach = this.dh.reduce((s, [, d, a]) => s + Math.abs(d) + Math.abs(a), 0);
    this.linkRadius = Math.max(reach / 30, 8);
    this.unitCylinder = this.#geometry(new THREE.CylinderGeometry(1, 1, 1, 20));
    const linkMaterial = this.#material(material(0x9aa5b1));
    const jointMaterial = this.#material(material(0x2f6f9f));
    this.links = [];
    for (let i = 0; i < 12; i++) {
      const m = new THREE.Mesh(this.unitCylinder, linkMaterial);
      m.name = `machine-link-${i}`;
      this.links.push(m);
      this.object.add(m);
    }
    this.joints = [];
    for (let i = 0; i < 6; i++) {
      const m = new THREE.Mesh(this.unitCylinder, jointMaterial);
      m.name = `machine-joint-${i + 1}`;
      this.joints.push(m);
      this.object.add(m);
    }
    const base = new THREE.Mesh(this.#geometry(new THREE.CylinderGeometry(this.linkRadius * 1.6, this.linkRadius * 1.8, this.linkRadius, 32).rotateX(Math.PI / 2)), linkMaterial);
    base.position.z = -this.linkRadius / 2;
    this.object.add(base);
    this.flange = this.#fixed(new THREE.Mesh(this.#geometry(new THREE.CylinderGeometry(this.linkRadius * 0.8, this.linkRadius * 0.8, 4, 24).rotateX(Math.PI / 2).translate(0, 0, -2)), jointMaterial), 'machine-flange');
    this.object.add(this.flange);
    // A floor grid under the robot (base frame z = 0 is DH frame 0).
    const grid = new THREE.GridHelper(reach, 10, 0x56606d, 0x3a424d);
    grid.rotateX(Math.PI / 2);
    this.disposables.push(grid.geometry, grid.material);
    this.object.add(grid);
  }

  // Put a unit cylinder between points a and b (THREE.Vector3) with the given radius; hidden when
  // the two coincide.
  #cylinder(mesh, a, b, radius) {
    const dir = new THREE.Vector3().subVectors(b, a);
    const len = dir.length();
    mesh.visible = len > 1e-6;
    if (!mesh.visible) return;
    mesh.position.addVectors(a, b).multiplyScalar(0.5);
    mesh.quaternion.setFromUnitVectors(UP, dir.divideScalar(len));
    mesh.scale.set(radius, len, radius);
  }

  /** Machine values of move s (6 numbers; the kind uses the first machineAxisCount). */
  valuesAt(s) {
    const m = this.preview.machine;
    return [m[6 * s], m[6 * s + 1], m[6 * s + 2], m[6 * s + 3], m[6 * s + 4], m[6 * s + 5]];
  }

  /** Part-frame end point of move s. */
  pointAt(s) {
    const p = this.preview.positions;
    return [p[6 * s + 3], p[6 * s + 4], p[6 * s + 5]];
  }

  /**
   * Pose the machine at the end of move s (clamped to 0..stepCount-1) with the material of moves
   * 0..s deposited. Returns {step, values, tipError}: tipError is measured in the scene (mm).
   */
  setStep(s) {
    if (this.stepCount === 0) return { step: -1, values: [], tipError: NaN };
    s = Math.min(Math.max(0, Math.floor(s)), this.stepCount - 1);
    this.step = s;
    const values = this.valuesAt(s);
    const profile = this.profile;
    if (this.posesFromCore) {
      const q = this.preview.poses;
      const o = 7 * s;
      this.platform.matrix.compose(new THREE.Vector3(q[o + 4], q[o + 5], q[o + 6]),
        new THREE.Quaternion(q[o], q[o + 1], q[o + 2], q[o + 3]), ONE);
    } else {
      this.platform.matrix.copy(matrixOf(platformTransform(profile, values)));
    }
    // Nozzle: tip at the machine-frame tip, local +Z along the machine-frame nozzle axis.
    const tip = new THREE.Vector3(...nozzleTip(profile, values));
    const axis = new THREE.Vector3(...nozzleAxisMachine(profile, values));
    this.nozzle.matrix.compose(tip, new THREE.Quaternion().setFromUnitVectors(new THREE.Vector3(0, 0, 1), axis), new THREE.Vector3(1, 1, 1));
    if (this.kind === 'robot6') this.#poseRobot(values);
    else {
      if (this.trunnion) this.trunnion.matrix.copy(matrixOf(trunnionTransform(profile, values)));
      // The X rail carries the carriage: at the nozzle's Y, at the carriage's height (head5: the
      // carriage point, where B and C turn the head, with an arm down to the tilted nozzle).
      const [x0, x1] = this.xRange;
      this.rail.scale.x = x1 - x0;
      if (this.kind === 'head5' || this.kind === 'head4') {
        const carriage = new THREE.Vector3(values[0], values[1], values[2]);
        this.rail.position.set((x0 + x1) / 2, carriage.y, carriage.z + this.carriage[2] / 2);
        this.#cylinder(this.headArm, carriage, tip.clone().addScaledVector(axis, this.nozzleLength), 4);
      } else {
        this.rail.position.set((x0 + x1) / 2, tip.y, tip.z + this.nozzleLength + this.carriage[2] / 2);
      }
    }
    this.deposit.geometry.setDrawRange(0, 2 * this.depositedBefore[s + 1]);
    const p = this.pointAt(s);
    this.point.position.set(p[0], p[1], p[2]);
    // The tip error, measured on the scene graph as drawn.
    this.object.updateMatrixWorld(true);
    const onPlatform = new THREE.Vector3(...p).applyMatrix4(this.platform.matrixWorld);
    this.tipError = onPlatform.distanceTo(this.tip.getWorldPosition(new THREE.Vector3()));
    return { step: s, values: values.slice(0, this.axisNames.length), tipError: this.tipError };
  }

  #poseRobot(q) {
    const frames = dhFrames(this.dh, q);
    const r = this.linkRadius;
    for (let i = 0; i < 6; i++) {
      const F = frames[i];
      const o = new THREE.Vector3(...origin4(F));
      const z = new THREE.Vector3(F[2], F[6], F[10]);
      // Joint i+1 turns about z_i at frame i's origin.
      this.#cylinder(this.joints[i], o.clone().addScaledVector(z, -r * 1.1), o.clone().addScaledVector(z, r * 1.1), r * 1.15);
      // Link i+1: d along z_i, then a along x_{i+1}, ending at frame i+1's origin.
      const elbow = o.clone().addScaledVector(z, this.dh[i][1]);
      this.#cylinder(this.links[2 * i], o, elbow, r);
      this.#cylinder(this.links[2 * i + 1], elbow, new THREE.Vector3(...origin4(frames[i + 1])), r);
    }
    this.flange.matrix.copy(matrixOf(frames[6]));
  }

  /** Release the GPU resources of the model (the preview's typed arrays stay the caller's). */
  dispose() {
    for (const d of this.disposables) d.dispose();
    this.disposables = [];
  }
}
