// SPDX-License-Identifier: MIT
// The machine animation's scene graph (web/machine-view.js) in Node, no WebGL needed: for every
// kind, a synthetic program whose part-frame points are the forward map of random machine values
// (stored as Float32, as the core sends them) puts the drawn nozzle tip on the drawn deposition
// point at every step; a program whose points are off by 1 mm shows a 1 mm tip error (so the
// measure is not blind); the robot's drawn links end at the DH frame origins; the deposit shown
// at step s is exactly the extruding moves 0..s.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import * as THREE from 'three';
import { MachineView } from '../../web/machine-view.js';
import { UR5_DH, dhFrames, forwardMap, origin4, platformTransform } from '../../web/machine-kinematics.js';

function rng(seed) {
  let x = seed >>> 0;
  return (lo = 0, hi = 1) => {
    x = (Math.imul(x, 1664525) + 1013904223) >>> 0;
    return lo + ((hi - lo) * x) / 4294967296;
  };
}

const PROFILES = {
  cartesian3: { kind: 'cartesian3', axis_limits: { X: [-110, 110], Y: [-110, 110], Z: [0, 250] } },
  rotary4: { kind: 'rotary4', pivot: [0, 0, 15], axis_limits: { A: [-60, 60] } },
  table5: { kind: 'table5', pivot: [3, -2, 10], axis_limits: { B: [-90, 90], C: [-360, 360] } },
  head5: { kind: 'head5', tip_offset: [0, 0, -60], axis_limits: { B: [-90, 90], C: [-360, 360] } },
  head4: { kind: 'head4', tilt_deg: 45, tip_offset: [0, 0, -40], axis_limits: { C: [-360, 360] } },
  robot6: {
    kind: 'robot6',
    dh: UR5_DH.map((r) => [...r]),
    flange_to_platform: [1, 0, 0, 0, 0, -1, 0, 0, 0, 0, -1, 60, 0, 0, 0, 1],
    nozzle_tip: [-420, -150, 250],
    nozzle_axis: [0, 0, 1],
    nozzle: { diameter: 0.4, cone_half_angle_deg: 40, cone_length: 25 },
  },
};

// S moves of random machine values; positions' segment ends are their part-frame tips.
function syntheticPreview(kind, S, seed, offset = [0, 0, 0]) {
  const r = rng(seed);
  const machine = new Float32Array(6 * S);
  const positions = new Float32Array(6 * S);
  const features = new Uint8Array(S);
  let prev = [0, 0, 0];
  for (let s = 0; s < S; s++) {
    const v = kind === 'robot6'
      ? [r(-3, 3), r(-2.5, -0.5), r(-2, 2), r(-3, 3), r(-3, 3), r(-3, 3)]
      : [r(-80, 80), r(-80, 80), r(0, 100), r(-60, 60), kind === 'table5' || kind === 'head5' ? r(-300, 300) : 0, 0];
    machine.set(v, 6 * s);
    const stored = Array.from(machine.subarray(6 * s, 6 * s + 6));
    const { tip } = forwardMap(PROFILES[kind], stored);
    const end = tip.map((x, i) => x + offset[i]);
    positions.set([...prev, ...end], 6 * s);
    prev = end;
    features[s] = s % 5 === 0 ? 0 : 1 + (s % 6);
  }
  return { positions, features, layers: new Uint32Array(S), machine };
}

const mesh = {
  positions: new Float32Array([-5, -5, 0, 5, -5, 0, 0, 5, 0, 0, 0, 8]),
  indices: new Uint32Array([0, 2, 1, 0, 1, 3, 1, 2, 3, 2, 0, 3]),
};

for (const kind of Object.keys(PROFILES)) {
  test(`${kind}: the drawn nozzle tip sits on the drawn deposition point at every step`, () => {
    const S = 400;
    const view = new MachineView(PROFILES[kind], syntheticPreview(kind, S, 17), mesh);
    assert.equal(view.stepCount, S);
    let worst = 0;
    for (let s = 0; s < S; s++) {
      const { tipError, step, values } = view.setStep(s);
      assert.equal(step, s);
      assert.equal(values.length, { cartesian3: 3, rotary4: 4, table5: 5, head4: 4, head5: 5, robot6: 6 }[kind]);
      worst = Math.max(worst, tipError);
    }
    // Float32 storage of values and points: well under 1e-3 mm.
    assert.ok(worst < 1e-3, `${kind}: worst tip error ${worst} mm`);
    // Clamping.
    assert.equal(view.setStep(-5).step, 0);
    assert.equal(view.setStep(1e9).step, S - 1);
    view.dispose();

    // Points shifted by 1 mm in the part frame: the scene shows a 1 mm error.
    const off = new MachineView(PROFILES[kind], syntheticPreview(kind, 50, 17, [0, 0.6, 0.8]), mesh);
    for (let s = 0; s < 50; s += 7) {
      const e = off.setStep(s).tipError;
      assert.ok(Math.abs(e - 1) < 1e-3, `${kind}: shifted points give ${e} mm`);
    }
    off.dispose();
  });
}

// Poses as the core sends them (preview.poses: quaternion x y z w, translation, float32), here made
// from the JS forward map's platform transform, shifted by `shift` (mm, machine frame).
function posesOf(kind, preview, shift = [0, 0, 0]) {
  const S = preview.features.length;
  const poses = new Float32Array(7 * S);
  const q = new THREE.Quaternion();
  const t = new THREE.Vector3();
  for (let s = 0; s < S; s++) {
    const values = Array.from(preview.machine.subarray(6 * s, 6 * s + 6));
    new THREE.Matrix4().set(...platformTransform(PROFILES[kind], values)).decompose(t, q, new THREE.Vector3());
    poses.set([q.x, q.y, q.z, q.w, t.x + shift[0], t.y + shift[1], t.z + shift[2]], 7 * s);
  }
  return poses;
}

test('the core\'s poses, when the preview has them, place the platform (and a wrong pose shows)', () => {
  for (const kind of Object.keys(PROFILES)) {
    const p = syntheticPreview(kind, 60, 29);
    const view = new MachineView(PROFILES[kind], { ...p, poses: posesOf(kind, p) }, mesh);
    assert.equal(view.posesFromCore, true);
    let worst = 0;
    for (let s = 0; s < 60; s++) worst = Math.max(worst, view.setStep(s).tipError);
    assert.ok(worst < 1e-3, `${kind}: worst tip error ${worst} mm with poses`);
    view.dispose();
    // Poses 1 mm off: the view follows them, not the machine values.
    const off = new MachineView(PROFILES[kind], { ...p, poses: posesOf(kind, p, [0.6, 0, -0.8]) }, mesh);
    for (let s = 0; s < 60; s += 9) {
      const e = off.setStep(s).tipError;
      assert.ok(Math.abs(e - 1) < 1e-3, `${kind}: poses shifted by 1 mm give ${e} mm`);
    }
    off.dispose();
    // Poses of the wrong length are ignored (the forward map places the platform).
    const short = new MachineView(PROFILES[kind], { ...p, poses: new Float32Array(7) }, mesh);
    assert.equal(short.posesFromCore, false);
    short.dispose();
  }
});

test('the deposit shown at step s is exactly the extruding moves 0..s', () => {
  const p = syntheticPreview('rotary4', 200, 3);
  const view = new MachineView(PROFILES.rotary4, p, mesh);
  for (const s of [0, 1, 4, 5, 6, 57, 199]) {
    view.setStep(s);
    const shown = view.deposit.geometry.drawRange.count / 2;
    let expected = 0;
    for (let k = 0; k <= s; k++) if (p.features[k] !== 0) expected++;
    assert.equal(shown, expected, `step ${s}`);
    // The segments drawn are those moves, in order.
    const index = view.deposit.geometry.index.array;
    for (let k = 0, j = 0; k <= s; k++) {
      if (p.features[k] === 0) continue;
      assert.equal(index[2 * j], 2 * k);
      j++;
    }
  }
});

test('robot6: the drawn links end at the DH frame origins; the flange is frame 6', () => {
  const p = syntheticPreview('robot6', 20, 9);
  const view = new MachineView(PROFILES.robot6, p, mesh);
  for (let s = 0; s < 20; s++) {
    view.setStep(s);
    view.object.updateMatrixWorld(true);
    const frames = dhFrames(UR5_DH, Array.from(p.machine.subarray(6 * s, 6 * s + 6)));
    for (let i = 0; i < 6; i++) {
      const link = view.links[2 * i + 1];
      if (!link.visible) continue;
      // The end of the unit cylinder (local y = +0.5) in world space.
      const end = new THREE.Vector3(0, 0.5, 0).applyMatrix4(link.matrixWorld);
      const o = origin4(frames[i + 1]);
      assert.ok(end.distanceTo(new THREE.Vector3(...o)) < 1e-6, `link ${i + 1} ends at frame ${i + 1}`);
    }
    const flange = new THREE.Vector3().setFromMatrixPosition(view.flange.matrixWorld);
    assert.ok(flange.distanceTo(new THREE.Vector3(...origin4(frames[6]))) < 1e-6);
  }
});

test('buffers that disagree are refused', () => {
  const p = syntheticPreview('table5', 10, 1);
  assert.throws(() => new MachineView(PROFILES.table5, { ...p, machine: p.machine.subarray(6) }, mesh), /disagrees/);
  assert.throws(() => new MachineView({ kind: 'delta' }, p, mesh), /unknown machine kind/);
});
