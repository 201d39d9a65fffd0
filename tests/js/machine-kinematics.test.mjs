// SPDX-License-Identifier: MIT
// The page's forward maps (web/machine-kinematics.js) against independent numbers:
//   - rotary4 / table5 points rotated by hand (quarter turns worked out on paper) and random
//     values against the formulas of PROGRAM-FORMAT.md written out with explicit trigonometry here;
//   - UR5 forward kinematics at the zero pose and the upright pose (positions and orientation
//     worked out link by link on paper), and at random joint vectors against a DH chain composed
//     here in a different form (rotation matrix and origin accumulated link by link);
//   - the animation's property for random values of every kind: platform transform * part-frame
//     tip = machine-frame nozzle tip, and the part-frame nozzle axis = platform rotation^T * u.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import {
  MACHINE_KINDS, UR5_DH, dhForward, dhFrames, forwardMap, invertRigid4, machineAxisCount,
  machineKind, multiply4, nozzleAxisMachine, nozzleTip, platformTransform, tipError,
  transformDirection4, transformPoint4, trunnionTransform,
} from '../../web/machine-kinematics.js';

const DEG = Math.PI / 180;

function near(actual, expected, tol, what) {
  assert.equal(actual.length, expected.length, `${what}: length`);
  const err = Math.max(...actual.map((x, i) => Math.abs(x - expected[i])));
  assert.ok(err <= tol, `${what}: got [${actual.map((x) => x.toFixed(6))}], expected [${expected}] (max error ${err})`);
}

// Deterministic random numbers (LCG), so failures reproduce.
function rng(seed) {
  let x = seed >>> 0;
  return (lo = 0, hi = 1) => {
    x = (Math.imul(x, 1664525) + 1013904223) >>> 0;
    return lo + ((hi - lo) * x) / 4294967296;
  };
}

const rotary4 = { kind: 'rotary4', pivot: [0, 0, 10], axis_limits: { A: [-60, 60] } };
const table5 = { kind: 'table5', pivot: [0, 0, 0], axis_limits: { B: [-90, 90], C: [-360, 360] } };

// A UR5 holding a platform 50 mm past the flange, turned half a turn about the flange X axis
// (so the platform's +Z faces away from the flange), under a fixed nozzle pointing down.
const ur5 = {
  kind: 'robot6',
  dh: UR5_DH.map((r) => [...r]),
  flange_to_platform: [1, 0, 0, 0, 0, -1, 0, 0, 0, 0, -1, 50, 0, 0, 0, 1],
  nozzle_tip: [-450, -191.45, 300],
  nozzle_axis: [0, 0, 1],
};

test('kind names and axis counts', () => {
  assert.deepEqual(MACHINE_KINDS, ['cartesian3', 'rotary4', 'table5', 'head4', 'head5', 'robot6']);
  assert.equal(machineKind('robot6-ur5'), 'robot6');
  assert.equal(machineKind({ kind: 'table5' }), 'table5');
  assert.equal(machineKind('delta'), null);
  assert.deepEqual(MACHINE_KINDS.map(machineAxisCount), [3, 4, 5, 4, 5, 6]);
  assert.throws(() => platformTransform({ kind: 'delta' }, [0, 0, 0]), /unknown machine kind/);
});

test('cartesian3: the tip is the machine position, the nozzle axis +Z', () => {
  const { tip, axis } = forwardMap({ kind: 'cartesian3' }, [12.5, -3, 7, 0, 0, 0]);
  near(tip, [12.5, -3, 7], 0, 'tip');
  near(axis, [0, 0, 1], 0, 'axis');
});

test('rotary4: a quarter turn about X through the pivot, worked out by hand', () => {
  // q = (1, 2, 3), P = (0, 0, 10): q - P = (1, 2, -7); Rx(90) (x, y, z) = (x, -z, y) -> (1, 7, 2);
  // + P -> m = (1, 7, 12). The nozzle axis in the part frame is Rx(90)^T +Z = (0, 1, 0).
  const m = [1, 7, 12, 90, 0, 0];
  const { tip, axis } = forwardMap(rotary4, m);
  near(tip, [1, 2, 3], 1e-12, 'rotary4 tip');
  near(axis, [0, 1, 0], 1e-12, 'rotary4 axis');
  near(transformPoint4(platformTransform(rotary4, m), [1, 2, 3]), [1, 7, 12], 1e-12, 'platform maps q to m');
  // A = -30: Rx(-30)(0, 0, -10) = (0, -10 sin 30, -10 cos 30) -> m = (0, -5, 10 - 8.660254).
  near(forwardMap(rotary4, [0, -5, 10 - 10 * Math.cos(30 * DEG), -30]).tip, [0, 0, 0], 1e-12, 'rotary4 origin at A = -30');
});

test('table5: B then C quarter turns, worked out by hand', () => {
  // B = C = 90, P = 0: Rz(90) X = Y, Ry(90) Y = Y -> part X lands on machine Y;
  // Rz(90) Z = Z, Ry(90) Z = X -> part Z lands on machine X; part Y: Rz(90) Y = -X, Ry(90)(-X) = Z.
  const W = platformTransform(table5, [0, 0, 0, 90, 90]);
  near(transformPoint4(W, [1, 0, 0]), [0, 1, 0], 1e-12, 'part X');
  near(transformPoint4(W, [0, 0, 1]), [1, 0, 0], 1e-12, 'part Z');
  near(transformPoint4(W, [0, 1, 0]), [0, 0, 1], 1e-12, 'part Y');
  // So the machine's +Z nozzle axis is the part's +Y.
  near(forwardMap(table5, [0, 0, 0, 90, 90]).axis, [0, 1, 0], 1e-12, 'table5 axis');
  // The trunnion alone carries B only: it maps part Z to machine X at B = 90 whatever C is.
  near(transformPoint4(trunnionTransform(table5, [0, 0, 0, 90, 37]), [0, 0, 1]), [1, 0, 0], 1e-12, 'trunnion');
  // Pivot off the origin: a point on the pivot stays put for any B, C.
  const t5 = { ...table5, pivot: [5, -4, 20] };
  near(forwardMap(t5, [5, -4, 20, 33, -71]).tip, [5, -4, 20], 1e-12, 'pivot fixed');
});

test('rotary4 and table5 at random values: the formulas of PROGRAM-FORMAT.md written out here', () => {
  const r = rng(11);
  for (let i = 0; i < 500; i++) {
    const q = [r(-50, 50), r(-50, 50), r(0, 60)];
    const P = [r(-20, 20), r(-20, 20), r(-10, 30)];
    // rotary4: m = P + Rx(A)(q - P).
    const A = r(-180, 180);
    const [dx, dy, dz] = [q[0] - P[0], q[1] - P[1], q[2] - P[2]];
    const ca = Math.cos(A * DEG);
    const sa = Math.sin(A * DEG);
    const m4 = [P[0] + dx, P[1] + ca * dy - sa * dz, P[2] + sa * dy + ca * dz];
    const f4 = forwardMap({ kind: 'rotary4', pivot: P }, [...m4, A, 0, 0]);
    near(f4.tip, q, 1e-9, `rotary4 #${i}`);
    near(f4.axis, [0, sa, ca], 1e-12, `rotary4 axis #${i}`);
    // table5: m = P + Ry(B) Rz(C)(q - P).
    const B = r(-90, 90);
    const C = r(-360, 360);
    const cb = Math.cos(B * DEG);
    const sb = Math.sin(B * DEG);
    const cc = Math.cos(C * DEG);
    const sc = Math.sin(C * DEG);
    const z1 = [cc * dx - sc * dy, sc * dx + cc * dy, dz];
    const m5 = [P[0] + cb * z1[0] + sb * z1[2], P[1] + z1[1], P[2] - sb * z1[0] + cb * z1[2]];
    const f5 = forwardMap({ kind: 'table5', pivot: P }, [...m5, B, C, 0]);
    near(f5.tip, q, 1e-9, `table5 #${i}`);
    // (Ry(B) Rz(C))^T Z = Rz(-C) (Ry(B)^T Z) = Rz(-C) (-sin B, 0, cos B).
    near(f5.axis, [-sb * cc, sb * sc, cb], 1e-12, `table5 axis #${i}`);
  }
});

test('head5: the tip hangs tip_offset from the carriage point, turned by B then C (by hand)', () => {
  const head5 = { kind: 'head5', tip_offset: [0, 0, -60] };
  // Untilted: the tip 60 mm below the carriage point, the axis +Z; the bed stays put.
  near(forwardMap(head5, [10, 20, 100, 0, 77]).tip, [10, 20, 40], 1e-12, 'vertical');
  near(forwardMap(head5, [10, 20, 100, 0, 77]).axis, [0, 0, 1], 1e-12, 'vertical axis');
  near(platformTransform(head5, [10, 20, 100, 30, 40]), [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1], 0, 'bed fixed');
  // B = 90: Ry(90) (0, 0, -60) = (-60, 0, 0), axis Ry(90) Z = X; then C = 90 turns X onto Y.
  near(forwardMap(head5, [0, 0, 100, 90, 0]).tip, [-60, 0, 100], 1e-12, 'B 90');
  near(forwardMap(head5, [0, 0, 100, 90, 0]).axis, [1, 0, 0], 1e-12, 'B 90 axis');
  near(forwardMap(head5, [0, 0, 100, 90, 90]).tip, [0, -60, 100], 1e-12, 'B 90 C 90');
  near(forwardMap(head5, [0, 0, 100, 90, 90]).axis, [0, 1, 0], 1e-12, 'B 90 C 90 axis');
  // Random values: u = (sin B cos C, sin B sin C, cos B) and tip = carriage - 60 u.
  const r = rng(5);
  for (let i = 0; i < 200; i++) {
    const v = [r(-100, 100), r(-100, 100), r(0, 200), r(-90, 90), r(-360, 360), 0];
    const [sb, cb, sc, cc] = [Math.sin(v[3] * DEG), Math.cos(v[3] * DEG), Math.sin(v[4] * DEG), Math.cos(v[4] * DEG)];
    const u = [sb * cc, sb * sc, cb];
    const f = forwardMap(head5, v);
    near(f.axis, u, 1e-12, `head5 axis #${i}`);
    near(f.tip, [v[0] - 60 * u[0], v[1] - 60 * u[1], v[2] - 60 * u[2]], 1e-9, `head5 tip #${i}`);
  }
});

test('head4: the nozzle leans tilt_deg, C turns it about Z (by hand)', () => {
  const head4 = { kind: 'head4', tilt_deg: 45, tip_offset: [0, 0, -40] };
  const s = Math.SQRT1_2;
  near(forwardMap(head4, [0, 0, 100, 0]).axis, [s, 0, s], 1e-12, 'C 0 leans toward +X');
  near(forwardMap(head4, [0, 0, 100, 0]).tip, [-40 * s, 0, 100 - 40 * s], 1e-12, 'C 0 tip');
  near(forwardMap(head4, [0, 0, 100, 90]).axis, [0, s, s], 1e-12, 'C 90 leans toward +Y');
  near(forwardMap(head4, [0, 0, 100, 90]).tip, [0, -40 * s, 100 - 40 * s], 1e-12, 'C 90 tip');
});

test('UR5 forward kinematics at the zero and upright poses (worked out link by link)', () => {
  // Zero pose: x = a2 + a3, y = -(d4 + d6), z = d1 - d5; flange axes x = X, y = Z, z = -Y.
  const F0 = dhForward(UR5_DH, [0, 0, 0, 0, 0, 0]);
  near([F0[3], F0[7], F0[11]], [-817.25, -191.45, 89.159 - 94.65], 1e-9, 'zero pose position');
  near([F0[0], F0[4], F0[8]], [1, 0, 0], 1e-12, 'zero pose x axis');
  near([F0[1], F0[5], F0[9]], [0, 0, 1], 1e-12, 'zero pose y axis');
  near([F0[2], F0[6], F0[10]], [0, -1, 0], 1e-12, 'zero pose z axis');
  // Upright pose q = (0, -90, 0, -90, 0, 0) degrees: the upper and fore arms point straight up,
  // the wrist 2 axis up: (0, -(d4 + d6), d1 - a2 - a3 + d5).
  const Fu = dhForward(UR5_DH, [0, -Math.PI / 2, 0, -Math.PI / 2, 0, 0]);
  near([Fu[3], Fu[7], Fu[11]], [0, -191.45, 89.159 + 425 + 392.25 + 94.65], 1e-9, 'upright position');
  near([Fu[2], Fu[6], Fu[10]], [0, -1, 0], 1e-12, 'upright tool z axis');
  // Frame origins of the upright pose: shoulder, elbow, wrist 1 on the vertical line x = y = 0.
  const frames = dhFrames(UR5_DH, [0, -Math.PI / 2, 0, -Math.PI / 2, 0, 0]);
  near([frames[2][3], frames[2][7], frames[2][11]], [0, 0, 89.159 + 425], 1e-9, 'elbow');
  near([frames[3][3], frames[3][7], frames[3][11]], [0, 0, 89.159 + 425 + 392.25], 1e-9, 'wrist 1');
  // Base joint turned 90 degrees: everything turns about Z (x, y) -> (-y, x).
  const Fr = dhForward(UR5_DH, [Math.PI / 2, 0, 0, 0, 0, 0]);
  near([Fr[3], Fr[7], Fr[11]], [191.45, -817.25, 89.159 - 94.65], 1e-9, 'q1 = 90 position');
});

// DH chain composed another way: orientation R (3x3, nested arrays) and origin p accumulated per
// link: p += R (a cos t, a sin t, d); R = R Rz(t) Rx(alpha).
function chainByHand(dh, q) {
  let R = [[1, 0, 0], [0, 1, 0], [0, 0, 1]];
  let p = [0, 0, 0];
  const mul = (A, B) => A.map((row) => [0, 1, 2].map((c) => row[0] * B[0][c] + row[1] * B[1][c] + row[2] * B[2][c]));
  for (let i = 0; i < 6; i++) {
    const [off, d, a, alpha] = dh[i];
    const t = q[i] + off;
    const local = [a * Math.cos(t), a * Math.sin(t), d];
    p = p.map((x, r) => x + R[r][0] * local[0] + R[r][1] * local[1] + R[r][2] * local[2]);
    const Rz = [[Math.cos(t), -Math.sin(t), 0], [Math.sin(t), Math.cos(t), 0], [0, 0, 1]];
    const Rx = [[1, 0, 0], [0, Math.cos(alpha), -Math.sin(alpha)], [0, Math.sin(alpha), Math.cos(alpha)]];
    R = mul(mul(R, Rz), Rx);
  }
  return { R, p };
}

test('UR5 forward kinematics at random joint vectors: same as a chain composed by hand', () => {
  const r = rng(5);
  for (let i = 0; i < 200; i++) {
    const q = Array.from({ length: 6 }, () => r(-2 * Math.PI, 2 * Math.PI));
    // Also exercise non-zero theta offsets.
    const dh = UR5_DH.map(([off, d, a, alpha]) => [off + (i % 2 ? r(-1, 1) : 0), d, a, alpha]);
    const F = dhForward(dh, q);
    const { R, p } = chainByHand(dh, q);
    near([F[3], F[7], F[11]], p, 1e-9, `position #${i}`);
    near([F[0], F[1], F[2], F[4], F[5], F[6], F[8], F[9], F[10]], R.flat(), 1e-12, `rotation #${i}`);
    near([F[12], F[13], F[14], F[15]], [0, 0, 0, 1], 0, `last row #${i}`);
    // The reach is bounded by the link lengths.
    assert.ok(Math.hypot(...p) <= 89.159 + 425 + 392.25 + 109.15 + 94.65 + 82.3);
  }
});

// Random rigid transform (row-major): rotation from a random unit quaternion, random translation.
function randomRigid(r) {
  let [w, x, y, z] = [r(-1, 1), r(-1, 1), r(-1, 1), r(-1, 1)];
  const n = Math.hypot(w, x, y, z);
  [w, x, y, z] = [w / n, x / n, y / n, z / n];
  return [
    1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y), r(-100, 100),
    2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x), r(-100, 100),
    2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y), r(-100, 100),
    0, 0, 0, 1,
  ];
}

test('every kind, random values: platform transform * part-frame tip = nozzle tip', () => {
  const r = rng(23);
  for (let i = 0; i < 300; i++) {
    const pivot = [r(-30, 30), r(-30, 30), r(-30, 30)];
    const profiles = [
      { kind: 'cartesian3' },
      { kind: 'rotary4', pivot },
      { kind: 'table5', pivot },
      { kind: 'head5', tip_offset: [r(-20, 20), r(-20, 20), r(-80, 0)] },
      { kind: 'head4', tilt_deg: r(-60, 60), tip_offset: [r(-20, 20), r(-20, 20), r(-80, 0)] },
      { ...ur5, flange_to_platform: randomRigid(r), nozzle_tip: [r(-600, 600), r(-600, 600), r(-200, 700)],
        nozzle_axis: [r(-1, 1), r(-1, 1), r(0.2, 1)] },
    ];
    for (const profile of profiles) {
      const values = profile.kind === 'robot6'
        ? Array.from({ length: 6 }, () => r(-Math.PI, Math.PI))
        : [r(-100, 100), r(-100, 100), r(0, 200), r(-180, 180), r(-360, 360), 0];
      const W = platformTransform(profile, values);
      const { tip, axis } = forwardMap(profile, values);
      near(transformPoint4(W, tip), nozzleTip(profile, values), 1e-9, `${profile.kind} #${i} tip`);
      assert.ok(tipError(profile, values, tip) < 1e-9);
      // A point 1 mm off the tip is 1 mm off.
      assert.ok(Math.abs(tipError(profile, values, [tip[0] + 1, tip[1], tip[2]]) - 1) < 1e-9);
      near(transformDirection4(W, axis), nozzleAxisMachine(profile, values), 1e-12, `${profile.kind} #${i} axis`);
      // Rigid: W^-1 W = I.
      near(multiply4(invertRigid4(W), W), [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1], 1e-9, 'rigid inverse');
      if (profile.kind === 'robot6') {
        // q = W^-1 N with W = FK(q) T, composed here from the hand-built chain.
        const { R, p } = chainByHand(profile.dh, values);
        const T = profile.flange_to_platform;
        const F = [...R[0], p[0], ...R[1], p[1], ...R[2], p[2], 0, 0, 0, 1];
        near(W, multiply4(F, T), 1e-9, `robot6 #${i} W = F T`);
      }
    }
  }
});
