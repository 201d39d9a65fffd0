#!/usr/bin/env node
// SPDX-License-Identifier: MIT
// Benchmark meshes (binary STL, generated, cached): build/bench/torus-100k.stl (100,000 triangles,
// genus 1, 80 x 80 x 20 mm), build/bench/sphere-1m.stl (1,000,000 triangles, 100 mm) and
// build/bench/sphere-1m-holes.stl: the same sphere with 1,000 holes (two neighbouring quads, four
// triangles, every 994 triangles: apart from each other, a six-point loop each) for the repair;
// build/bench/spheres-2x50k-overlap.stl: two 50,000-triangle spheres (50 and 40 mm) overlapping
// as separate shells, for the union of overlapping shells; build/bench/box-100k-tjunctions.stl: an
// 80 x 60 x 40 mm box whose six faces are gridded independently (T-junctions on every edge), which
// the repair zips; build/bench/box-100k-cracks.stl: the same with each face shrunk by 1e-4 about
// its centre (the cracks open), which the repair rebuilds from inside/outside samples.
// Usage: node scripts/gen-bench-models.mjs [OUT_DIR=build/bench]
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { sphereStl, torusStl, writeBinaryStl } from '../tests/js/fixtures/meshes.js';

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');

export const BENCH_MODELS = [
  { name: 'torus-100k.stl', triangles: 100000, make: () => torusStl(30, 10, 400, 125) },
  { name: 'sphere-1m.stl', triangles: 1000000, make: () => sphereStl(50, 1000, 501) },
  { name: 'sphere-1m-holes.stl', triangles: 996000, make: () => withHoles(sphereStl(50, 1000, 501), 1000, 994, 4) },
  { name: 'spheres-2x50k-overlap.stl', triangles: 100000,
    make: () => joinStl(sphereStl(25, 250, 101), sphereStl(20, 250, 101), [25, 7, 5]) },
  { name: 'box-100k-tjunctions.stl', triangles: 100100, make: () => tJunctionBoxStl(0) },
  { name: 'box-100k-cracks.stl', triangles: 100100, make: () => tJunctionBoxStl(1e-4) },
];

/**
 * The 80 x 60 x 40 box, each face an independent grid of quads (two triangles each), outward; each
 * face scaled about its centre by 1 - shrink (shrink > 0 opens the T-junctions into cracks).
 */
function tJunctionBoxStl(shrink) {
  const v = [];
  const t = [];
  const patch = (o, u, w, nu, nw) => {
    const base = v.length / 3;
    for (let i = 0; i <= nu; ++i) {
      for (let j = 0; j <= nw; ++j) {
        for (let k = 0; k < 3; ++k) {
          const c = o[k] + (u[k] + w[k]) / 2;
          v.push(c + (o[k] + (u[k] * i) / nu + (w[k] * j) / nw - c) * (1 - shrink));
        }
      }
    }
    for (let i = 0; i < nu; ++i) {
      for (let j = 0; j < nw; ++j) {
        const a = base + i * (nw + 1) + j, b = a + nw + 1;
        t.push(a, b, b + 1, a, b + 1, a + 1);
      }
    }
  };
  const [X, Y, Z] = [80, 60, 40];
  patch([0, 0, 0], [0, Y, 0], [X, 0, 0], 89, 101);  // bottom, normal -z
  patch([0, 0, Z], [X, 0, 0], [0, Y, 0], 103, 87);  // top
  patch([0, 0, 0], [X, 0, 0], [0, 0, Z], 113, 71);  // y = 0
  patch([0, Y, 0], [0, 0, Z], [X, 0, 0], 67, 127);  // y = Y
  patch([0, 0, 0], [0, 0, Z], [0, Y, 0], 79, 97);   // x = 0
  patch([X, 0, 0], [0, Y, 0], [0, 0, Z], 93, 85);   // x = X
  return writeBinaryStl(new Float32Array(v), t);
}

/** Binary STL bytes of a's triangles and b's moved by offset (two shells in one file). */
function joinStl(a, b, offset) {
  const src = [new Uint8Array(a), new Uint8Array(b)];
  const counts = src.map((s) => new DataView(s.buffer, s.byteOffset).getUint32(80, true));
  const out = new Uint8Array(84 + 50 * (counts[0] + counts[1]));
  new DataView(out.buffer).setUint32(80, counts[0] + counts[1], true);
  out.set(src[0].subarray(84), 84);
  out.set(src[1].subarray(84), 84 + 50 * counts[0]);
  const view = new DataView(out.buffer);
  for (let t = counts[0]; t < counts[0] + counts[1]; ++t) {
    for (let v = 0; v < 3; ++v) {
      for (let k = 0; k < 3; ++k) {
        const at = 84 + 50 * t + 12 + 12 * v + 4 * k;
        view.setFloat32(at, view.getFloat32(at, true) + offset[k], true);
      }
    }
  }
  return out.buffer;
}

/** Binary STL bytes without `size` triangles at 500 + k * every, k < holes (an aligned quad pair). */
function withHoles(stl, holes, every, size) {
  const src = new Uint8Array(stl);
  const n = new DataView(src.buffer, src.byteOffset).getUint32(80, true);
  const drop = new Uint8Array(n);
  for (let k = 0; k < holes; ++k) drop.fill(1, 500 + k * every, 500 + k * every + size);
  const kept = n - holes * size;
  const out = new Uint8Array(84 + 50 * kept);
  out.set(src.subarray(0, 80));
  new DataView(out.buffer).setUint32(80, kept, true);
  let at = 84;
  for (let t = 0; t < n; ++t) {
    if (drop[t]) continue;
    out.set(src.subarray(84 + 50 * t, 134 + 50 * t), at);
    at += 50;
  }
  return out.buffer;
}

/** Write the models that are missing (or have the wrong size); returns their paths. */
export function generateBenchModels(outDir = path.join(ROOT, 'build/bench')) {
  fs.mkdirSync(outDir, { recursive: true });
  const files = {};
  for (const m of BENCH_MODELS) {
    const file = path.join(outDir, m.name);
    const size = 84 + 50 * m.triangles;
    if (!fs.existsSync(file) || fs.statSync(file).size !== size) {
      const bytes = m.make();
      if (bytes.byteLength !== size) throw new Error(`${m.name}: ${bytes.byteLength} bytes, expected ${size}`);
      fs.writeFileSync(file, new Uint8Array(bytes));
      console.error(`[gen-bench-models] wrote ${file} (${m.triangles} triangles)`);
    }
    files[m.name] = file;
  }
  return files;
}

if (process.argv[1] && path.resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  generateBenchModels(process.argv[2] ? path.resolve(process.argv[2]) : undefined);
}
