// SPDX-License-Identifier: MIT
// Forward maps of the machine kinds of ../shared/PROGRAM-FORMAT.md ("Machine kinds"), in plain JS
// for the page's machine animation (no three.js here, so Node tests load it directly).
//
// Conventions:
//   - 4x4 matrices are arrays of 16 numbers, ROW-major (as `flange_to_platform` in the machine
//     JSON and as THREE.Matrix4.set() takes them); points are [x, y, z].
//   - `profile` is the machine JSON object of the program header (report.machine_profile): kind,
//     pivot, axis_limits; robot6 also dh (6 rows [theta_offset, d, a, alpha], mm/rad),
//     flange_to_platform (16 numbers), nozzle_tip and nozzle_axis (robot base frame).
//   - `values` are the machine values in the kind's order: X Y Z (mm) then A, or B C (degrees);
//     q1..q6 (radians) for robot6 (preview.machine, 6 per segment).
//   - The platform transform maps part-frame points into the machine frame (robot6: the robot base
//     frame). With it, every kind has the same tip property: platform(values) * tip_part =
//     nozzleTip(values), where nozzleTip is (X, Y, Z) for G-code kinds whose bed moves, (X, Y, Z) +
//     Rz(C) Ry(B) tip_offset for head5, Rz(C) Ry(tilt_deg) tip_offset for head4 (the bed is fixed,
//     the head turns) and the fixed nozzle_tip
//     for robot6.

/** Machine kinds (profile.kind values). Built-in profile names may differ (robot6-ur5). */
export const MACHINE_KINDS = Object.freeze(['cartesian3', 'rotary4', 'table5', 'head4', 'head5', 'robot6']);

const DEG = Math.PI / 180;

/** The kind of a profile or profile name: 'robot6-ur5' -> 'robot6'; unknown -> null. */
export function machineKind(profileOrName) {
  const s = typeof profileOrName === 'string' ? profileOrName : profileOrName && profileOrName.kind;
  if (typeof s !== 'string') return null;
  if (MACHINE_KINDS.includes(s)) return s;
  if (s.startsWith('robot6')) return 'robot6';
  return null;
}

/** Number of machine values a kind uses (3, 4, 5, 6; 0 when unknown). */
export function machineAxisCount(kind) {
  return { cartesian3: 3, rotary4: 4, table5: 5, head4: 4, head5: 5, robot6: 6 }[machineKind(kind)] || 0;
}

/** Axis names of a kind in value order. */
export function machineAxisNames(kind) {
  switch (machineKind(kind)) {
    case 'cartesian3': return ['X', 'Y', 'Z'];
    case 'rotary4': return ['X', 'Y', 'Z', 'A'];
    case 'table5':
    case 'head5': return ['X', 'Y', 'Z', 'B', 'C'];
    case 'head4': return ['X', 'Y', 'Z', 'C'];
    case 'robot6': return ['q1', 'q2', 'q3', 'q4', 'q5', 'q6'];
    default: return [];
  }
}

// ---- 4x4 row-major helpers ----------------------------------------------------------------------

export function identity4() {
  return [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1];
}

/** a * b (row-major). */
export function multiply4(a, b) {
  const out = new Array(16);
  for (let r = 0; r < 4; r++) {
    for (let c = 0; c < 4; c++) {
      out[4 * r + c] = a[4 * r] * b[c] + a[4 * r + 1] * b[4 + c] + a[4 * r + 2] * b[8 + c] + a[4 * r + 3] * b[12 + c];
    }
  }
  return out;
}

/** Product of several matrices, left to right. */
export function compose4(...ms) {
  return ms.reduce((acc, m) => multiply4(acc, m), identity4());
}

export function translation4([x, y, z]) {
  return [1, 0, 0, x, 0, 1, 0, y, 0, 0, 1, z, 0, 0, 0, 1];
}

/** Right-handed rotation about X by `rad` radians. */
export function rotationX4(rad) {
  const c = Math.cos(rad);
  const s = Math.sin(rad);
  return [1, 0, 0, 0, 0, c, -s, 0, 0, s, c, 0, 0, 0, 0, 1];
}

export function rotationY4(rad) {
  const c = Math.cos(rad);
  const s = Math.sin(rad);
  return [c, 0, s, 0, 0, 1, 0, 0, -s, 0, c, 0, 0, 0, 0, 1];
}

export function rotationZ4(rad) {
  const c = Math.cos(rad);
  const s = Math.sin(rad);
  return [c, -s, 0, 0, s, c, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1];
}

/** Inverse of a rigid transform (rotation + translation): [R^T, -R^T t]. */
export function invertRigid4(m) {
  const out = identity4();
  for (let r = 0; r < 3; r++) for (let c = 0; c < 3; c++) out[4 * r + c] = m[4 * c + r];
  for (let r = 0; r < 3; r++) {
    out[4 * r + 3] = -(out[4 * r] * m[3] + out[4 * r + 1] * m[7] + out[4 * r + 2] * m[11]);
  }
  return out;
}

/** m * [p, 1] (the point's image). */
export function transformPoint4(m, p) {
  return [0, 1, 2].map((r) => m[4 * r] * p[0] + m[4 * r + 1] * p[1] + m[4 * r + 2] * p[2] + m[4 * r + 3]);
}

/** The rotation part of m applied to a direction. */
export function transformDirection4(m, v) {
  return [0, 1, 2].map((r) => m[4 * r] * v[0] + m[4 * r + 1] * v[1] + m[4 * r + 2] * v[2]);
}

/** Translation column of m. */
export function origin4(m) {
  return [m[3], m[7], m[11]];
}

export function distance3(a, b) {
  return Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

// ---- Denavit-Hartenberg (standard, distal) ----------------------------------------------------

/** One standard DH link: Rz(theta + offset) Tz(d) Tx(a) Rx(alpha); row [offset, d, a, alpha]. */
export function dhLink([offset, d, a, alpha], theta) {
  const ct = Math.cos(theta + offset);
  const st = Math.sin(theta + offset);
  const ca = Math.cos(alpha);
  const sa = Math.sin(alpha);
  return [
    ct, -st * ca, st * sa, a * ct,
    st, ct * ca, -ct * sa, a * st,
    0, sa, ca, d,
    0, 0, 0, 1,
  ];
}

/**
 * DH frames of a chain: frames[0] = base (identity), frames[i] = link_1 ... link_i (i = 1..n);
 * frames[n] is the flange. dh: n rows [theta_offset, d, a, alpha]; q: n joint values (rad).
 */
export function dhFrames(dh, q) {
  const frames = [identity4()];
  for (let i = 0; i < dh.length; i++) frames.push(multiply4(frames[i], dhLink(dh[i], q[i])));
  return frames;
}

/** Flange pose FK(q) in the robot base frame. */
export function dhForward(dh, q) {
  return dhFrames(dh, q)[dh.length];
}

// ---- machine forward maps ---------------------------------------------------------------------

function pivotOf(profile) {
  const p = profile && profile.pivot;
  return Array.isArray(p) && p.length === 3 ? p.map(Number) : [0, 0, 0];
}

/** The UR5 (CB series) standard DH table of PROGRAM-FORMAT.md (mm, rad). */
export const UR5_DH = Object.freeze([
  [0, 89.159, 0, Math.PI / 2],
  [0, 0, -425, 0],
  [0, 0, -392.25, 0],
  [0, 109.15, 0, Math.PI / 2],
  [0, 94.65, 0, -Math.PI / 2],
  [0, 82.3, 0, 0],
].map(Object.freeze));

function flangeToPlatform(profile) {
  const t = profile && profile.flange_to_platform;
  if (Array.isArray(t) && t.length === 16) return t.map(Number);
  if (Array.isArray(t) && t.length === 4 && t.every((r) => Array.isArray(r) && r.length === 4)) return t.flat().map(Number);
  return identity4();
}

/** The profile's DH rows (robot6), as arrays of 4 numbers. */
export function dhTable(profile) {
  const dh = profile && profile.dh;
  if (!Array.isArray(dh) || dh.length !== 6) throw new RangeError('robot6 profile needs a dh table of 6 rows');
  return dh.map((row) => {
    if (Array.isArray(row) && row.length === 4) return row.map(Number);
    if (row && typeof row === 'object') return [row.theta_offset ?? 0, row.d ?? 0, row.a ?? 0, row.alpha ?? 0].map(Number);
    throw new RangeError('dh rows must be [theta_offset, d, a, alpha]');
  });
}

/**
 * Platform transform: part frame -> machine frame (robot6: robot base frame).
 *   cartesian3, head4 and head5 (the bed is fixed): identity; rotary4: T(P) Rx(A) T(-P); table5: T(P) Ry(B) Rz(C) T(-P);
 *   robot6: W = FK_DH(q) * flange_to_platform.
 */
export function platformTransform(profile, values) {
  const kind = machineKind(profile);
  const P = pivotOf(profile);
  const minusP = P.map((x) => -x);
  switch (kind) {
    case 'cartesian3':
    case 'head4':
    case 'head5':
      return identity4();
    case 'rotary4':
      return compose4(translation4(P), rotationX4(values[3] * DEG), translation4(minusP));
    case 'table5':
      return compose4(translation4(P), rotationY4(values[3] * DEG), rotationZ4(values[4] * DEG), translation4(minusP));
    case 'robot6':
      return multiply4(dhForward(dhTable(profile), values), flangeToPlatform(profile));
    default:
      throw new RangeError(`unknown machine kind ${profile && profile.kind}`);
  }
}

/** table5 only: the trunnion (cradle) transform T(P) Ry(B) T(-P), which carries the C platform. */
export function trunnionTransform(profile, values) {
  const P = pivotOf(profile);
  return compose4(translation4(P), rotationY4(values[3] * DEG), translation4(P.map((x) => -x)));
}

/** The head's turn (4x4, row-major): head5 Rz(C) Ry(B); head4 Rz(C) Ry(tilt_deg), C = values[3]. */
export function headTurn(profile, values) {
  if (machineKind(profile) === 'head4') return multiply4(rotationZ4(values[3] * DEG), rotationY4(Number(profile.tilt_deg || 0) * DEG));
  return multiply4(rotationZ4(values[4] * DEG), rotationY4(values[3] * DEG));
}

const isHead = (profile) => machineKind(profile) === 'head4' || machineKind(profile) === 'head5';

function tipOffset(profile) {
  const o = profile && profile.tip_offset;
  return Array.isArray(o) && o.length === 3 ? o.map(Number) : [0, 0, 0];
}

/**
 * Nozzle tip in the machine frame: (X, Y, Z) for G-code kinds whose bed moves, the carriage point
 * plus the turned tip offset for head4 and head5, the fixed nozzle_tip for robot6.
 */
export function nozzleTip(profile, values) {
  const kind = machineKind(profile);
  if (kind === 'robot6') {
    const n = profile.nozzle_tip;
    return Array.isArray(n) && n.length === 3 ? n.map(Number) : [0, 0, 0];
  }
  if (isHead(profile)) {
    const o = transformDirection4(headTurn(profile, values), tipOffset(profile));
    return [values[0] + o[0], values[1] + o[1], values[2] + o[2]];
  }
  return [values[0], values[1], values[2]];
}

/**
 * Nozzle axis (unit, tip -> hot end) in the machine frame: +Z, nozzle_axis for robot6, the head's
 * turn of +Z for head4 and head5 (values needed only there).
 */
export function nozzleAxisMachine(profile, values) {
  if (isHead(profile)) return transformDirection4(headTurn(profile, values), [0, 0, 1]);
  if (machineKind(profile) === 'robot6' && Array.isArray(profile.nozzle_axis)) {
    const u = profile.nozzle_axis.map(Number);
    const n = Math.hypot(...u);
    return n > 0 ? u.map((x) => x / n) : [0, 0, 1];
  }
  return [0, 0, 1];
}

/**
 * Forward map of PROGRAM-FORMAT.md: the part-frame tip and nozzle axis for machine values.
 * @returns {{tip: number[], axis: number[]}}
 */
export function forwardMap(profile, values) {
  const inv = invertRigid4(platformTransform(profile, values));
  return {
    tip: transformPoint4(inv, nozzleTip(profile, values)),
    axis: transformDirection4(inv, nozzleAxisMachine(profile, values)),
  };
}

/** |platform(values) * partPoint - nozzleTip(values)| in mm: 0 when the tip is on the point. */
export function tipError(profile, values, partPoint) {
  return distance3(transformPoint4(platformTransform(profile, values), partPoint), nozzleTip(profile, values));
}
