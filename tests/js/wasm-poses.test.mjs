// SPDX-License-Identifier: MIT
// The platform poses the core hands the page (preview.poses, built with GLM in
// core/pipeline/preview.cpp: per segment a unit quaternion x y z w and a translation) against an
// independent computation: the page's own forward map (web/machine-kinematics.js
// platformTransform) of the segment's machine values. For every machine kind, with methods that
// turn the platform (multidir's parts on rotary4 and table5, the UR5), in slices and in the
// replay of the written program: the matrix three.js composes from a pose equals the JS transform
// within float32 rounding, and it puts the segment's part-frame end on the nozzle tip.
import { before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import * as THREE from 'three';
import { CI, REPO, loadShipped, wasmUnavailable } from './wasm-support.mjs';
import { nozzleTip, platformTransform } from '../../web/machine-kinematics.js';

const why = wasmUnavailable();
if (why && CI) throw new Error(`wasm tests cannot run under CI: ${why}`);

const DEMO = path.join(REPO, 'web', 'models', 'demo-overhang.stl');

/**
 * Worst differences of the poses against the JS forward map: matrix entries (rotation part, and
 * translation in mm), the tip distance (mm), the quaternions' norms, the smallest dot product of
 * consecutive quaternions, and the largest platform rotation seen (deg; so a case that never
 * turns cannot pass for one that does).
 */
function comparePoses(profile, preview) {
  const { poses, machine, positions, features } = preview;
  const S = features.length;
  assert.ok(poses instanceof Float32Array, 'preview.poses is a Float32Array');
  assert.equal(poses.length, 7 * S, 'preview.poses: 7 values per segment');
  const m = new THREE.Matrix4();
  const q = new THREE.Quaternion();
  const t = new THREE.Vector3();
  const one = new THREE.Vector3(1, 1, 1);
  const out = { rotation: 0, translation: 0, tip: 0, norm: 0, dot: 1, turn: 0 };
  for (let s = 0; s < S; s++) {
    const o = 7 * s;
    q.set(poses[o], poses[o + 1], poses[o + 2], poses[o + 3]);
    out.norm = Math.max(out.norm, Math.abs(q.length() - 1));
    if (s > 0) {
      const p = o - 7;
      out.dot = Math.min(out.dot, poses[o] * poses[p] + poses[o + 1] * poses[p + 1] + poses[o + 2] * poses[p + 2] + poses[o + 3] * poses[p + 3]);
    }
    out.turn = Math.max(out.turn, (2 * Math.acos(Math.min(1, Math.abs(q.w) / q.length())) * 180) / Math.PI);
    t.set(poses[o + 4], poses[o + 5], poses[o + 6]);
    m.compose(t, q.normalize(), one);
    const values = Array.from(machine.subarray(6 * s, 6 * s + 6));
    const js = platformTransform(profile, values);  // row-major
    const e = m.elements;  // column-major
    for (let r = 0; r < 3; r++) {
      for (let c = 0; c < 3; c++) out.rotation = Math.max(out.rotation, Math.abs(e[4 * c + r] - js[4 * r + c]));
      out.translation = Math.max(out.translation, Math.abs(e[12 + r] - js[4 * r + 3]));
    }
    const end = new THREE.Vector3(positions[6 * s + 3], positions[6 * s + 4], positions[6 * s + 5]).applyMatrix4(m);
    const [x, y, z] = nozzleTip(profile, values);
    out.tip = Math.max(out.tip, Math.hypot(end.x - x, end.y - y, end.z - z));
  }
  return out;
}

describe('platform poses of the preview (wasm in Node)', { skip: why ? `skipped: ${why}` : false }, () => {
  let m;
  let demo;
  before(async () => {
    ({ module: m } = await loadShipped());
    demo = fs.readFileSync(DEMO);
  });

  const cases = [
    // [machine, settings, least rotation the case must show (deg)]
    ['cartesian3', { method: 'planar' }, 0],
    ['rotary4', { method: 'multidir' }, 1],
    ['table5', { method: 'multidir' }, 1],
    ['robot6-ur5', { method: 'planar', layer_height: 0.4 }, 1],
  ];
  for (const [machine, settings, leastTurn] of cases) {
    test(`${machine} ${settings.method}: poses equal the JS forward map within float32, in the slice and its replay`, (t) => {
      const r = m.slice(demo, 'demo-overhang.stl', { machine, ...settings });
      const profile = r.report.machine_profile;
      const sliced = comparePoses(profile, r.preview);
      const replay = m.replay(r.program);
      assert.ok(replay.preview.features.length > r.preview.features.length / 2, 'the replay has segments');
      const replayed = comparePoses(replay.profile, replay.preview);
      t.diagnostic(`${machine} ${settings.method}: ${r.preview.features.length} segments, worst rotation entry ` +
        `${sliced.rotation.toExponential(2)}, translation ${sliced.translation.toExponential(2)} mm, tip ` +
        `${sliced.tip.toExponential(2)} mm, largest turn ${sliced.turn.toFixed(1)} deg; replay tip ${replayed.tip.toExponential(2)} mm`);
      for (const [name, d] of [['slice', sliced], ['replay', replayed]]) {
        assert.ok(d.norm < 1e-6, `${name}: unit quaternions (${d.norm})`);
        assert.ok(d.dot >= 0, `${name}: consecutive quaternions in one hemisphere (${d.dot})`);
        assert.ok(d.rotation < 1e-6, `${name}: rotation entries within float32 (${d.rotation})`);
        // float32 of translations up to a few hundred mm (the UR5's base frame): ulp ~3e-5 mm.
        assert.ok(d.translation < 1e-4 * Math.max(1, profile.kind === 'robot6' ? 10 : 1), `${name}: translation (${d.translation} mm)`);
        assert.ok(d.tip < 2e-3, `${name}: the pose puts the segment end on the nozzle tip (${d.tip} mm)`);
      }
      assert.ok(sliced.turn >= leastTurn, `${machine} ${settings.method}: the platform turns ${sliced.turn} deg`);
    });
  }
});
