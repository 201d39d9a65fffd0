// SPDX-License-Identifier: MIT
// Generates the page's demo model for the geodesic method (paper 002): a small branching tree (a
// trunk forking into three tilted branches) as one closed, outward-oriented OBJ mesh.
//
// The solid is the implicit f(p) <= 0 of a smooth union of capsules (signed distances blended by
// a polynomial smooth minimum), cut flat by the platform plane z = 0, sampled on a regular grid
// and polygonised by marching tetrahedra on the grid's Freudenthal split (every cube into six
// tets around its main diagonal, the same way in every cube, so neighbouring cubes share their
// face diagonals). The zero set of a piecewise-linear function that is zero at no grid vertex is
// a closed 2-manifold: each crossing point is made once per grid edge and shared by every tet
// around it. Crossings are kept 5% of the edge away from its ends (no sliver triangle shorter than
// that) and every triangle faces from the inside corners of its tet to the outside ones.
// Grid planes sit half a step off z = 0, so the flat base lies exactly on the platform.
//
// Only +, -, *, / and sqrt are used (all correctly rounded in IEEE double), so the bytes are the
// same on every machine (tests/js/demo-tree.test.mjs checks the committed file).
//
// Usage: node scripts/make-demo-tree.mjs [out.obj]   (default web/models/demo-tree.obj)
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

/**
 * Default parameters (mm): capsules [ax, ay, az, bx, by, bz, radius], the blend width of the
 * smooth union, the grid step, and the decimals written.
 */
export const TREE_PARAMS = {
  capsules: [
    [0, 0, -6, 0, 0, 20, 6.5],         // trunk (reaching below the platform: the cut makes the base)
    [0, 0, 18, 13, 0, 40, 4],          // branch leaning towards +X (about 31 degrees)
    [0, 0, 18, -7, 11.5, 44, 3.8],     // towards -X +Y (about 27 degrees)
    [0, 0, 18, -7.5, -11, 38, 3.6],    // towards -X -Y (about 34 degrees)
  ],
  blend: 3,
  step: 1.2,
  decimals: 3,
};

/** Signed distance of p to the capsule c (negative inside). */
function capsule(px, py, pz, c) {
  const [ax, ay, az, bx, by, bz, r] = c;
  const ux = bx - ax, uy = by - ay, uz = bz - az;
  const wx = px - ax, wy = py - ay, wz = pz - az;
  let t = (wx * ux + wy * uy + wz * uz) / (ux * ux + uy * uy + uz * uz);
  t = t < 0 ? 0 : t > 1 ? 1 : t;
  const dx = wx - t * ux, dy = wy - t * uy, dz = wz - t * uz;
  return Math.sqrt(dx * dx + dy * dy + dz * dz) - r;
}

/** Polynomial smooth minimum of a and b with blend width k (equal to min when |a - b| >= k). */
function smoothMin(a, b, k) {
  const d = k - Math.abs(a - b);
  if (d <= 0) return a < b ? a : b;
  return (a < b ? a : b) - (d * d) / (4 * k);
}

/** The tree's implicit function: negative inside, positive outside, the base cut at z = 0. */
export function treeField(x, y, z, p = TREE_PARAMS) {
  let f = capsule(x, y, z, p.capsules[0]);
  for (let i = 1; i < p.capsules.length; i++) f = smoothMin(f, capsule(x, y, z, p.capsules[i]), p.blend);
  return f > -z ? f : -z;
}

// The six tets of a cube (corner c = bx + 2 by + 4 bz): the monotone paths 0 -> 7 along the axes.
const CUBE_TETS = [[0, 1, 3, 7], [0, 1, 5, 7], [0, 2, 3, 7], [0, 2, 6, 7], [0, 4, 5, 7], [0, 4, 6, 7]];

/**
 * Build the tree mesh.
 * @returns {{positions: Float64Array, indices: Uint32Array, grid: number[]}} #V*3 positions (mm,
 *   rounded to p.decimals), #F*3 indices, outward-oriented; grid: the sample counts per axis
 */
export function buildTreeMesh(p = TREE_PARAMS) {
  const h = p.step;
  let lo = [Infinity, Infinity, 0];
  let hi = [-Infinity, -Infinity, -Infinity];
  for (const c of p.capsules) {
    for (let a = 0; a < 3; a++) {
      lo[a] = Math.min(lo[a], c[a] - c[6], c[3 + a] - c[6]);
      hi[a] = Math.max(hi[a], c[a] + c[6], c[3 + a] + c[6]);
    }
  }
  lo = [Math.floor(lo[0] / h) - 2, Math.floor(lo[1] / h) - 2, -2];
  hi = [Math.ceil(hi[0] / h) + 2, Math.ceil(hi[1] / h) + 2, Math.ceil(hi[2] / h) + 2];
  const n = [hi[0] - lo[0] + 1, hi[1] - lo[1] + 1, hi[2] - lo[2] + 1];
  const coord = (a, i) => (a === 2 ? (lo[2] + i + 0.5) * h : (lo[a] + i) * h);
  const N = n[0] * n[1] * n[2];
  const value = new Float64Array(N);
  for (let k = 0; k < n[2]; k++) {
    for (let j = 0; j < n[1]; j++) {
      for (let i = 0; i < n[0]; i++) {
        let f = treeField(coord(0, i), coord(1, j), coord(2, k), p);
        // A zero at a grid vertex would pinch the surface there: nudge it outside.
        if (f === 0) f = 1e-9;
        value[i + n[0] * (j + n[1] * k)] = f;
      }
    }
  }
  const scale = 10 ** p.decimals;
  const round = (x) => {
    const r = Math.round(x * scale) / scale;
    return r === 0 ? 0 : r;  // no negative zero in the text
  };
  const positions = [];
  const edgeVertex = new Map();
  const vertexOn = (a, b) => {
    const key = a < b ? a * N + b : b * N + a;
    let v = edgeVertex.get(key);
    if (v !== undefined) return v;
    const fa = value[a];
    const fb = value[b];
    let t = fa / (fa - fb);
    t = t < 0.05 ? 0.05 : t > 0.95 ? 0.95 : t;
    const ia = a % n[0], ja = Math.floor(a / n[0]) % n[1], ka = Math.floor(a / (n[0] * n[1]));
    const ib = b % n[0], jb = Math.floor(b / n[0]) % n[1], kb = Math.floor(b / (n[0] * n[1]));
    v = positions.length / 3;
    positions.push(
      round(coord(0, ia) + t * (coord(0, ib) - coord(0, ia))),
      round(coord(1, ja) + t * (coord(1, jb) - coord(1, ja))),
      round(coord(2, ka) + t * (coord(2, kb) - coord(2, ka))),
    );
    edgeVertex.set(key, v);
    return v;
  };
  const pos = (id) => [coord(0, id % n[0]), coord(1, Math.floor(id / n[0]) % n[1]), coord(2, Math.floor(id / (n[0] * n[1])))];
  const indices = [];
  // Emit triangle (a, b, c) of crossing vertices facing along `out` (inside -> outside).
  const emit = (a, b, c, out) => {
    const P = (v) => [positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]];
    const [A, B, C] = [P(a), P(b), P(c)];
    const u = [B[0] - A[0], B[1] - A[1], B[2] - A[2]];
    const w = [C[0] - A[0], C[1] - A[1], C[2] - A[2]];
    const nx = u[1] * w[2] - u[2] * w[1], ny = u[2] * w[0] - u[0] * w[2], nz = u[0] * w[1] - u[1] * w[0];
    if (nx * out[0] + ny * out[1] + nz * out[2] >= 0) indices.push(a, b, c);
    else indices.push(a, c, b);
  };
  const corner = new Array(8);
  for (let k = 0; k + 1 < n[2]; k++) {
    for (let j = 0; j + 1 < n[1]; j++) {
      for (let i = 0; i + 1 < n[0]; i++) {
        for (let c = 0; c < 8; c++) corner[c] = (i + (c & 1)) + n[0] * ((j + ((c >> 1) & 1)) + n[1] * (k + ((c >> 2) & 1)));
        let any = 0;
        for (let c = 0; c < 8; c++) any |= value[corner[c]] < 0 ? 1 : 2;
        if (any !== 3) continue;  // the cube is wholly inside or outside
        for (const tet of CUBE_TETS) {
          const ids = tet.map((c) => corner[c]);
          const inside = ids.filter((id) => value[id] < 0);
          const outside = ids.filter((id) => value[id] >= 0);
          if (inside.length === 0 || outside.length === 0) continue;
          const centroid = (list) => {
            const s = [0, 0, 0];
            for (const id of list) {
              const q = pos(id);
              s[0] += q[0] / list.length;
              s[1] += q[1] / list.length;
              s[2] += q[2] / list.length;
            }
            return s;
          };
          const ci = centroid(inside);
          const co = centroid(outside);
          const out = [co[0] - ci[0], co[1] - ci[1], co[2] - ci[2]];
          if (inside.length === 1 || outside.length === 1) {
            const [apex, others] = inside.length === 1 ? [inside[0], outside] : [outside[0], inside];
            emit(vertexOn(apex, others[0]), vertexOn(apex, others[1]), vertexOn(apex, others[2]), out);
          } else {
            // Two inside (a, b), two outside (c, d): the quad ac, ad, bd, bc.
            const [a, b] = inside;
            const [c, d] = outside;
            const ac = vertexOn(a, c), ad = vertexOn(a, d), bd = vertexOn(b, d), bc = vertexOn(b, c);
            emit(ac, ad, bd, out);
            emit(ac, bd, bc, out);
          }
        }
      }
    }
  }
  return { positions: Float64Array.from(positions), indices: Uint32Array.from(indices), grid: n };
}

const TREE_TITLE = 'omnislice demo: branching tree for the geodesic method (scripts/make-demo-tree.mjs)';

/**
 * OBJ text of a mesh (positions written with `decimals` decimals, no trailing zeros) under a
 * one-line `title` comment.
 */
export function toObj(mesh, decimals = TREE_PARAMS.decimals, title = TREE_TITLE) {
  const { positions: P, indices: I } = mesh;
  const lines = [`# ${title}`];
  const num = (x) => String(Number(x.toFixed(decimals)));
  for (let v = 0; v < P.length / 3; v++) lines.push(`v ${num(P[3 * v])} ${num(P[3 * v + 1])} ${num(P[3 * v + 2])}`);
  for (let f = 0; f < I.length / 3; f++) lines.push(`f ${I[3 * f] + 1} ${I[3 * f + 1] + 1} ${I[3 * f + 2] + 1}`);
  return `${lines.join('\n')}\n`;
}

/** The demo tree's OBJ text. */
export function demoTreeObj(p = TREE_PARAMS) {
  return toObj(buildTreeMesh(p), p.decimals);
}

if (process.argv[1] && path.resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
  const out = path.resolve(process.argv[2] || path.join(root, 'web', 'models', 'demo-tree.obj'));
  const mesh = buildTreeMesh();
  const text = toObj(mesh);
  fs.mkdirSync(path.dirname(out), { recursive: true });
  fs.writeFileSync(out, text);
  let zMax = 0;
  for (let v = 2; v < mesh.positions.length; v += 3) zMax = Math.max(zMax, mesh.positions[v]);
  console.log(`${path.relative(process.cwd(), out)}: ${mesh.positions.length / 3} vertices, ${mesh.indices.length / 3} faces, `
    + `${zMax.toFixed(1)} mm tall, ${text.length} bytes`);
}
