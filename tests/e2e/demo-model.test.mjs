// SPDX-License-Identifier: MIT
// The bundled demo model: committed bytes equal the generator's output (deterministic, up to
// date), and the committed STL, parsed independently here, is a closed, consistently outward-
// oriented solid whose volume matches the profile area times the depth, with overhang faces at
// 30/45/60 degrees from vertical and a flat bridge underside.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { buildDemoMesh, toBinaryStl, profileArea, DEMO_PARAMS } from '../../scripts/make-demo-model.mjs';

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
const STL = path.join(ROOT, 'web', 'models', 'demo-overhang.stl');

function parseBinaryStl(buf) {
  const count = buf.readUInt32LE(80);
  assert.equal(buf.length, 84 + 50 * count, 'binary STL size matches its triangle count');
  const tris = [];
  for (let f = 0; f < count; f++) {
    const o = 84 + 50 * f;
    const n = [0, 1, 2].map((k) => buf.readFloatLE(o + 4 * k));
    const v = [0, 1, 2].map((j) => [0, 1, 2].map((k) => buf.readFloatLE(o + 12 + 12 * j + 4 * k)));
    tris.push({ n, v });
  }
  return tris;
}

const sub = (a, b) => a.map((x, i) => x - b[i]);
const crossV = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];

test('committed demo model is the generator output, deterministic and small', () => {
  const committed = fs.readFileSync(STL);
  const a = toBinaryStl(buildDemoMesh());
  const b = toBinaryStl(buildDemoMesh());
  assert.ok(a.equals(b), 'two generator runs give the same bytes');
  assert.ok(committed.equals(a), 'web/models/demo-overhang.stl is up to date (run node scripts/make-demo-model.mjs)');
  assert.ok(committed.length < 200 * 1024);
});

test('demo model is closed, oriented outwards, and has the intended volume', () => {
  const tris = parseBinaryStl(fs.readFileSync(STL));
  // Weld bit-identical coordinates.
  const ids = new Map();
  const id = (p) => {
    const k = p.join(',');
    if (!ids.has(k)) ids.set(k, ids.size);
    return ids.get(k);
  };
  const directed = new Map();
  let volume = 0;
  for (const { n, v } of tris) {
    const t = v.map(id);
    assert.equal(new Set(t).size, 3, 'no collapsed triangle');
    for (let k = 0; k < 3; k++) {
      const key = `${t[k]}>${t[(k + 1) % 3]}`;
      directed.set(key, (directed.get(key) || 0) + 1);
    }
    const c = crossV(sub(v[1], v[0]), sub(v[2], v[0]));
    const len = Math.hypot(...c);
    assert.ok(len > 1e-6, 'no zero-area triangle');
    assert.ok(dot(c, n) / len > 0.999, 'stored facet normal agrees with the winding');
    volume += dot(v[0], crossV(v[1], v[2])) / 6;
  }
  for (const [key, uses] of directed) {
    const [a, b] = key.split('>');
    assert.equal(uses, 1, `directed edge ${key} used once`);
    assert.equal(directed.get(`${b}>${a}`), 1, `edge ${key} has exactly one opposite half-edge`);
  }
  // Euler characteristic of a genus-1 surface (the extruded profile has one hole): V - E + F = 0.
  const V = ids.size, E = directed.size / 2, F = tris.length;
  assert.equal(V - E + F, 0, 'genus 1 (one tunnel under the bridge)');
  const expected = profileArea() * DEMO_PARAMS.depth;
  assert.ok(Math.abs(volume - expected) / expected < 1e-5, `volume ${volume} vs ${expected}`);
});

test('demo model has overhangs at 30/45/60 degrees and a bridge underside', () => {
  const tris = parseBinaryStl(fs.readFileSync(STL));
  const overhangs = new Set();
  let bridgeArea = 0;
  for (const { n, v } of tris) {
    const zMin = Math.min(...v.map((p) => p[2]));
    if (n[2] < -1e-3 && n[2] > -0.999) overhangs.add(Math.round((Math.asin(-n[2]) * 180) / Math.PI));
    if (n[2] < -0.999 && zMin > 1e-3) bridgeArea += Math.hypot(...crossV(sub(v[1], v[0]), sub(v[2], v[0]))) / 2;
  }
  assert.deepEqual([...overhangs].sort((a, b) => a - b), [30, 45, 60]);
  const expectedBridge = DEMO_PARAMS.bridgeSpan * DEMO_PARAMS.depth;
  assert.ok(Math.abs(bridgeArea - expectedBridge) < 1e-3, `bridge underside ${bridgeArea} mm2`);
});

// The second demo: the open saddle of paper 003 (S1) for the surface method.
test('committed saddle demo is the generator output: an open grid on z = (x^2 - y^2) / R, normals up', async () => {
  const { demoSaddleObj, SADDLE_PARAMS } = await import('../../scripts/make-demo-saddle.mjs');
  const file = path.join(ROOT, 'web', 'models', 'demo-saddle.obj');
  const committed = fs.readFileSync(file, 'utf8');
  assert.equal(demoSaddleObj(), demoSaddleObj(), 'deterministic');
  assert.equal(committed, demoSaddleObj(), 'web/models/demo-saddle.obj is up to date (run node scripts/make-demo-saddle.mjs)');
  assert.ok(committed.length < 300 * 1024, `${committed.length} bytes`);
  const { R, half, n } = SADDLE_PARAMS;
  const v = [];
  const f = [];
  for (const line of committed.split('\n')) {
    const [kind, ...rest] = line.trim().split(/\s+/);
    if (kind === 'v') v.push(rest.map(Number));
    if (kind === 'f') f.push(rest.map((x) => Number(x) - 1));
  }
  assert.equal(v.length, (n + 1) ** 2);
  assert.equal(f.length, 2 * n * n);
  for (const [x, y, z] of v) {
    assert.ok(Math.abs(x) <= half + 1e-9 && Math.abs(y) <= half + 1e-9, 'inside the square');
    assert.ok(Math.abs(z - (x * x - y * y) / R) < 1e-4, `on the saddle at (${x}, ${y})`);
  }
  // Every triangle faces up (projected area counter-clockwise) and the projections tile the square.
  let area = 0;
  const edges = new Map();
  for (const t of f) {
    const [a, b, c] = t.map((i) => v[i]);
    const cross2 = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    assert.ok(cross2 > 0, 'counter-clockwise seen from +z');
    area += cross2 / 2;
    for (let k = 0; k < 3; k++) {
      const key = `${t[k]}>${t[(k + 1) % 3]}`;
      assert.ok(!edges.has(key), 'each directed edge once (consistent orientation)');
      edges.set(key, true);
    }
  }
  assert.ok(Math.abs(area - (2 * half) ** 2) < 1e-6 * (2 * half) ** 2, `projected area ${area}`);
  // Open: the boundary edges (no opposite edge) are the 4 n edges around the square.
  const boundary = [...edges.keys()].filter((k) => !edges.has(k.split('>').reverse().join('>')));
  assert.equal(boundary.length, 4 * n);
});
