// SPDX-License-Identifier: MIT
// The demos made of capsules: the geodesic method's tree (scripts/make-demo-tree.mjs) and the
// first visit's post with three arms (scripts/make-demo-arms.mjs). For each, the committed OBJ is
// the generator's output (two runs give the same bytes), and the committed file, parsed here on
// its own, is a closed 2-manifold (every edge shared by exactly two faces, every vertex's faces one
// fan), consistently and outwardly oriented (each directed edge once, positive volume), a sphere
// topologically (V - E + F = 2), with no zero-area face, standing on a flat base on z = 0, whose
// volume is close to the implicit solid's (sampled independently on a fine grid).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { TREE_PARAMS, demoTreeObj, treeField } from '../../scripts/make-demo-tree.mjs';
import { ARMS_PARAMS, demoArmsObj } from '../../scripts/make-demo-arms.mjs';

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
/** Each demo: its committed file, generator, parameters, height range (mm) and sampling box. */
const DEMOS = [
  { name: 'tree', script: 'make-demo-tree.mjs', make: demoTreeObj, params: TREE_PARAMS, height: [40, 60],
    box: [[-20, 25], [-20, 20], [0, 55]] },
  { name: 'arms', script: 'make-demo-arms.mjs', make: demoArmsObj, params: ARMS_PARAMS, height: [35, 45],
    box: [[-14, 22], [-20, 20], [0, 45]] },
];

/** Parse OBJ text: v and f lines only (1-based indices), anything else is an error here. */
function parseObj(text) {
  const v = [];
  const f = [];
  for (const [n, line] of text.split('\n').entries()) {
    const s = line.trim();
    if (s === '' || s.startsWith('#')) continue;
    const [kind, ...rest] = s.split(/\s+/);
    if (kind === 'v') {
      assert.equal(rest.length, 3, `line ${n + 1}: three coordinates`);
      const p = rest.map(Number);
      assert.ok(p.every(Number.isFinite), `line ${n + 1}: finite coordinates`);
      v.push(p);
    } else if (kind === 'f') {
      assert.equal(rest.length, 3, `line ${n + 1}: triangles only`);
      f.push(rest.map((x) => Number(x) - 1));
    } else {
      assert.fail(`line ${n + 1}: unexpected '${kind}'`);
    }
  }
  for (const t of f) for (const i of t) assert.ok(Number.isInteger(i) && i >= 0 && i < v.length, `face index ${i + 1} in range`);
  return { v, f };
}

const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];

for (const { name, script, make, params, height, box } of DEMOS) {
  const OBJ = path.join(ROOT, 'web', 'models', `demo-${name}.obj`);

  test(`committed demo ${name} is the generator output: deterministic, 10k-30k triangles, under 600 kB`, () => {
    const a = make();
    const b = make();
    assert.equal(a, b, 'two generator runs give the same bytes');
    assert.equal(fs.readFileSync(OBJ, 'utf8'), a, `web/models/demo-${name}.obj is up to date (run node scripts/${script})`);
    const faces = (a.match(/^f /gm) || []).length;
    assert.ok(faces >= 10_000 && faces <= 30_000, `${faces} triangles`);
    assert.ok(a.length < 600 * 1024, `${a.length} bytes`);
  });

  test(`demo ${name} is closed, manifold, outward-oriented, genus 0, without zero-area faces`, () => {
    const { v, f } = parseObj(fs.readFileSync(OBJ, 'utf8'));
    const directed = new Map();
    const undirected = new Map();
    const around = new Map();  // vertex -> [[next, prev] per face]: its link edges
    let volume = 0;
    let minArea = Infinity;
    for (const t of f) {
      assert.equal(new Set(t).size, 3, `face ${t} repeats a vertex`);
      for (let k = 0; k < 3; k++) {
        const a = t[k];
        const b = t[(k + 1) % 3];
        const key = `${a}>${b}`;
        assert.ok(!directed.has(key), `directed edge ${key} used twice (inconsistent orientation)`);
        directed.set(key, true);
        const u = a < b ? `${a},${b}` : `${b},${a}`;
        undirected.set(u, (undirected.get(u) || 0) + 1);
        if (!around.has(a)) around.set(a, []);
        around.get(a).push([b, t[(k + 2) % 3]]);
      }
      const [A, B, C] = t.map((i) => v[i]);
      const n = cross(sub(B, A), sub(C, A));
      minArea = Math.min(minArea, Math.sqrt(dot(n, n)) / 2);
      volume += dot(A, cross(B, C)) / 6;
    }
    for (const [key, uses] of undirected) assert.equal(uses, 2, `edge ${key} shared by ${uses} faces`);
    for (const key of directed.keys()) {
      const [a, b] = key.split('>');
      assert.ok(directed.has(`${b}>${a}`), `edge ${key} has its opposite half-edge`);
    }
    // Vertex-manifold: the link edges (next -> prev of each face at the vertex) form one cycle.
    assert.equal(around.size, v.length, 'every vertex is used');
    for (const [vertex, link] of around) {
      const next = new Map(link);
      assert.equal(next.size, link.length, `vertex ${vertex}: link edges unique`);
      let at = link[0][0];
      let steps = 0;
      do {
        at = next.get(at);
        steps++;
      } while (at !== undefined && at !== link[0][0] && steps <= link.length);
      assert.equal(steps, link.length, `vertex ${vertex}: its ${link.length} faces form one fan`);
    }
    assert.equal(v.length - undirected.size + f.length, 2, 'Euler characteristic 2 (one closed genus-0 surface)');
    assert.ok(volume > 0, `signed volume ${volume} mm3 is positive (outward)`);
    assert.ok(minArea > 1e-5, `smallest face ${minArea} mm2`);
    // The base: a flat face patch on z = 0 and nothing below it; about 40-60 mm tall.
    let zMin = Infinity;
    let zMax = -Infinity;
    let baseArea = 0;
    for (const p of v) {
      zMin = Math.min(zMin, p[2]);
      zMax = Math.max(zMax, p[2]);
    }
    for (const t of f) {
      const [A, B, C] = t.map((i) => v[i]);
      if (A[2] === 0 && B[2] === 0 && C[2] === 0) {
        const n = cross(sub(B, A), sub(C, A));
        assert.ok(n[2] < 0, 'base faces point down');
        baseArea += -n[2] / 2;
      }
    }
    assert.equal(zMin, 0);
    assert.ok(zMax >= height[0] && zMax <= height[1], `height ${zMax} mm`);
    const r = params.capsules[0][6];
    // The faces with all three corners on z = 0 cover the trunk's disc less a rim of about a grid step.
    const inner = r - 1.5 * params.step;
    assert.ok(baseArea > Math.PI * inner * inner && baseArea < Math.PI * r * r,
      `base area ${baseArea} mm2 between the discs of radius ${inner} and ${r} mm`);
    // The volume against the implicit solid sampled at cell centres on a 0.4 mm grid.
    const h = 0.4;
    let inside = 0;
    for (let x = box[0][0]; x < box[0][1]; x += h) {
      for (let y = box[1][0]; y < box[1][1]; y += h) {
        for (let z = box[2][0]; z < box[2][1]; z += h) if (treeField(x + h / 2, y + h / 2, z + h / 2, params) < 0) inside++;
      }
    }
    const sampled = inside * h * h * h;
    assert.ok(Math.abs(volume - sampled) / sampled < 0.03, `mesh volume ${volume.toFixed(0)} vs sampled ${sampled.toFixed(0)} mm3`);
  });
}
