// SPDX-License-Identifier: MIT
// Generates the page's bundled demo model: a parametric overhang test piece written as a closed,
// outward-oriented binary STL (deterministic: same parameters give the same bytes).
//
// The piece is a profile in the XZ plane extruded along +Y:
//   - a base slab,
//   - three fins whose right faces overhang at 30, 45 and 60 degrees from vertical,
//   - a flat bridge between two pillars (the profile has one rectangular hole under the bridge).
// The profile's caps are triangulated by splitting it along a vertical cut through the hole into two
// simple polygons and ear-clipping each; the cut's end points are vertices of both halves and of the
// side walls, so every edge is shared by exactly two triangles.
//
// Usage: node scripts/make-demo-model.mjs [out.stl]   (default web/models/demo-overhang.stl)
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

/** Default parameters (mm, degrees). */
export const DEMO_PARAMS = {
  baseHeight: 4,
  depth: 20,            // extrusion length along Y
  finWidth: 5,          // fin foot width along X
  finHeight: 10,        // fin height above the base
  finGap: 4,            // clearance between an overhang tip and the next feature
  overhangDegrees: [30, 45, 60],
  pillarWidth: 4,
  bridgeSpan: 16,       // hole width under the bridge
  bridgeClearance: 10,  // hole height (base top to bridge underside)
  bridgeThickness: 3,
  margin: 3,            // base slab beyond the first fin and the last pillar
};

/**
 * Build the profile: outer ring counter-clockwise and hole ring clockwise, in (x, z), plus the X of
 * the vertical cut through the hole.
 */
export function demoProfile(p = DEMO_PARAMS) {
  const hb = p.baseHeight;
  const top = [];  // points of the upper outline, left to right, starting above x = 0
  let x = p.margin;
  top.push([0, hb], [x, hb]);
  for (const deg of p.overhangDegrees) {
    // Rounded to a micrometre so the profile's coordinates are short decimals.
    const reach = Math.round(p.finHeight * Math.tan((deg * Math.PI) / 180) * 1000) / 1000;
    top.push([x, hb + p.finHeight]);                    // vertical left face
    top.push([x + p.finWidth + reach, hb + p.finHeight]); // flat top
    top.push([x + p.finWidth, hb]);                      // overhanging right face
    x += p.finWidth + reach + p.finGap;
    top.push([x, hb]);
  }
  const bridgeTop = hb + p.bridgeClearance + p.bridgeThickness;
  const holeLeft = x + p.pillarWidth;
  const holeRight = holeLeft + p.bridgeSpan;
  const length = holeRight + p.pillarWidth + p.margin;
  const cutX = (holeLeft + holeRight) / 2;
  top.push([x, bridgeTop], [cutX, bridgeTop], [holeRight + p.pillarWidth, bridgeTop]);
  top.push([holeRight + p.pillarWidth, hb], [length, hb]);
  // Outer ring, counter-clockwise: along the bottom left to right, then the top outline right to left.
  const outer = [[0, 0], [cutX, 0], [length, 0]];
  for (let i = top.length - 1; i >= 0; i--) outer.push(top[i]);
  // Hole ring, clockwise (seen with x right, z up), with the cut's crossing points as vertices.
  const holeTop = hb + p.bridgeClearance;
  const hole = [[holeLeft, hb], [holeLeft, holeTop], [cutX, holeTop], [holeRight, holeTop], [holeRight, hb], [cutX, hb]];
  return { outer: dedupe(outer), hole, cutX, length, height: Math.max(bridgeTop, hb + p.finHeight) };
}

function dedupe(ring) {
  return ring.filter((q, i) => {
    const r = ring[(i + ring.length - 1) % ring.length];
    return q[0] !== r[0] || q[1] !== r[1];
  });
}

function cross(o, a, b) {
  return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

// Closed point-in-triangle test (points on an edge count as inside); the triangle is counter-clockwise.
function inTriangle(q, a, b, c) {
  return cross(a, b, q) >= 0 && cross(b, c, q) >= 0 && cross(c, a, q) >= 0;
}

/**
 * Ear-clip a simple counter-clockwise polygon given as indices into pts. Ears need a strictly
 * convex tip, so collinear vertices never produce zero-area triangles.
 * @returns {number[][]} triangles (index triples, counter-clockwise)
 */
export function earClip(poly, pts) {
  const ring = poly.slice();
  const tris = [];
  let guard = ring.length * ring.length + 10;
  while (ring.length > 3 && guard-- > 0) {
    let clipped = false;
    for (let i = 0; i < ring.length; i++) {
      const ia = ring[(i + ring.length - 1) % ring.length];
      const ib = ring[i];
      const ic = ring[(i + 1) % ring.length];
      const [a, b, c] = [pts[ia], pts[ib], pts[ic]];
      if (cross(a, b, c) <= 1e-12) continue;
      const blocked = ring.some((j) => j !== ia && j !== ib && j !== ic && inTriangle(pts[j], a, b, c));
      if (blocked) continue;
      tris.push([ia, ib, ic]);
      ring.splice(i, 1);
      clipped = true;
      break;
    }
    if (!clipped) throw new Error('earClip: polygon is not simple');
  }
  if (ring.length === 3) {
    if (cross(pts[ring[0]], pts[ring[1]], pts[ring[2]]) <= 1e-12) throw new Error('earClip: degenerate remainder');
    tris.push(ring);
  }
  return tris;
}

/**
 * Build the demo mesh.
 * @returns {{positions: Float32Array, indices: Uint32Array}} #V*3 positions (mm), #F*3 indices,
 *   outward-oriented, closed.
 */
export function buildDemoMesh(p = DEMO_PARAMS) {
  const { outer, hole, cutX } = demoProfile(p);
  const pts = [...outer, ...hole];
  const n = pts.length;
  const outerIdx = outer.map((_, i) => i);
  const holeIdx = hole.map((_, i) => outer.length + i);
  const find = (x, z) => pts.findIndex((q) => q[0] === x && q[1] === z);
  const hb = p.baseHeight;
  const holeTop = hb + p.bridgeClearance;
  const bottomCut = find(cutX, 0), holeBottomCut = find(cutX, hb), holeTopCut = find(cutX, holeTop);
  const topCut = pts.findIndex((q, i) => i < outer.length && q[0] === cutX && q[1] > holeTop);
  // Walk a ring from index `from` to `to` (inclusive) in ring order.
  const walk = (ring, from, to) => {
    const out = [];
    let k = ring.indexOf(from);
    for (;;) {
      out.push(ring[k]);
      if (ring[k] === to) return out;
      k = (k + 1) % ring.length;
    }
  };
  // Right half (x >= cutX), counter-clockwise: outer bottom cut -> ... -> outer top cut, down the
  // cut to the hole top, hole ring (clockwise, i.e. counter-clockwise for this half) round the right
  // side to the hole bottom, down the cut.
  const right = [...walk(outerIdx, bottomCut, topCut), ...walk(holeIdx, holeTopCut, holeBottomCut)];
  const left = [...walk(outerIdx, topCut, bottomCut), ...walk(holeIdx, holeBottomCut, holeTopCut)];
  const capTris = [...earClip(right, pts), ...earClip(left, pts)];

  const positions = new Float32Array(n * 2 * 3);
  pts.forEach(([x, z], i) => {
    positions.set([x, 0, z], i * 3);
    positions.set([x, p.depth, z], (n + i) * 3);
  });
  const faces = [];
  // Cap at y = 0 faces -Y: a counter-clockwise (x, z) triangle already has normal -Y.
  for (const [a, b, c] of capTris) faces.push([a, b, c]);
  for (const [a, b, c] of capTris) faces.push([n + a, n + c, n + b]);
  for (const ring of [outerIdx, holeIdx]) {
    for (let k = 0; k < ring.length; k++) {
      const a = ring[k], b = ring[(k + 1) % ring.length];
      faces.push([a, n + b, b], [a, n + a, n + b]);
    }
  }
  return { positions, indices: Uint32Array.from(faces.flat()) };
}

/** Binary STL bytes of a mesh (facet normals computed from the vertex order). */
export function toBinaryStl(mesh, header = 'omnislice demo: overhang test piece 30/45/60 deg + bridge') {
  const { positions: P, indices: I } = mesh;
  const count = I.length / 3;
  const buf = Buffer.alloc(84 + 50 * count);
  buf.write(header.slice(0, 80).padEnd(80, ' '), 0, 'latin1');
  buf.writeUInt32LE(count, 80);
  let o = 84;
  for (let f = 0; f < count; f++) {
    const v = [0, 1, 2].map((k) => [P[I[3 * f + k] * 3], P[I[3 * f + k] * 3 + 1], P[I[3 * f + k] * 3 + 2]]);
    const e1 = v[1].map((x, k) => x - v[0][k]);
    const e2 = v[2].map((x, k) => x - v[0][k]);
    const nrm = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]];
    const len = Math.hypot(...nrm) || 1;
    for (const x of nrm) { buf.writeFloatLE(x / len, o); o += 4; }
    for (const q of v) for (const x of q) { buf.writeFloatLE(x, o); o += 4; }
    buf.writeUInt16LE(0, o); o += 2;
  }
  return buf;
}

/**
 * Independent checks used by the generator and its test: every undirected edge used by exactly two
 * faces, no directed edge repeated (consistent orientation), positive signed volume, no
 * zero-area face.
 */
export function checkClosedOriented(mesh) {
  const { positions: P, indices: I } = mesh;
  const undirected = new Map();
  const directed = new Set();
  let volume = 0;
  let minArea2 = Infinity;
  const V = (i) => [P[3 * i], P[3 * i + 1], P[3 * i + 2]];
  for (let f = 0; f < I.length / 3; f++) {
    const t = [I[3 * f], I[3 * f + 1], I[3 * f + 2]];
    for (let k = 0; k < 3; k++) {
      const a = t[k], b = t[(k + 1) % 3];
      const key = a < b ? `${a},${b}` : `${b},${a}`;
      undirected.set(key, (undirected.get(key) || 0) + 1);
      const d = `${a}>${b}`;
      if (directed.has(d)) return { ok: false, reason: `directed edge ${d} repeated` };
      directed.add(d);
    }
    const [a, b, c] = t.map(V);
    volume += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6;
    const e1 = b.map((x, k) => x - a[k]), e2 = c.map((x, k) => x - a[k]);
    const cx = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]];
    minArea2 = Math.min(minArea2, Math.hypot(...cx));
  }
  for (const [key, uses] of undirected) {
    if (uses !== 2) return { ok: false, reason: `edge ${key} used by ${uses} faces` };
  }
  if (!(minArea2 > 1e-9)) return { ok: false, reason: 'zero-area face' };
  if (!(volume > 0)) return { ok: false, reason: `signed volume ${volume} not positive` };
  return { ok: true, volume, faces: I.length / 3, edges: undirected.size };
}

/** Exact area of the profile (shoelace), so the test can compare the mesh volume to area x depth. */
export function profileArea(p = DEMO_PARAMS) {
  const { outer, hole } = demoProfile(p);
  const shoelace = (r) => r.reduce((s, q, i) => s + cross([0, 0], q, r[(i + 1) % r.length]), 0) / 2;
  return shoelace(outer) + shoelace(hole);
}

if (process.argv[1] && path.resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
  const out = path.resolve(process.argv[2] || path.join(root, 'web', 'models', 'demo-overhang.stl'));
  const mesh = buildDemoMesh();
  const check = checkClosedOriented(mesh);
  if (!check.ok) {
    console.error(`make-demo-model: generated mesh fails its check: ${check.reason}`);
    process.exit(1);
  }
  const bytes = toBinaryStl(mesh);
  fs.mkdirSync(path.dirname(out), { recursive: true });
  fs.writeFileSync(out, bytes);
  console.log(`${path.relative(process.cwd(), out)}: ${check.faces} faces, volume ${check.volume.toFixed(1)} mm3, ${bytes.length} bytes`);
}
