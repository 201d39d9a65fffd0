// SPDX-License-Identifier: MIT
// Generates the page's second bundled demo model: the open saddle surface z = (x^2 - y^2) / R of
// paper 003 (S1) as OBJ text, for the surface method's iso-planar paths. Deterministic: the same
// parameters give the same bytes (tests/e2e/demo-model.test.mjs checks the committed file).
//
// Usage: node scripts/make-demo-saddle.mjs [out.obj]   (default web/models/demo-saddle.obj)
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { saddleObj } from '../tests/js/fixtures/meshes.js';

/** Default parameters: R (mm), half side of the square (mm), quads per side. */
export const SADDLE_PARAMS = { R: 100, half: 37.5, n: 40 };

/** The demo saddle's OBJ text. */
export function demoSaddleObj(p = SADDLE_PARAMS) {
  return saddleObj(p.R, p.half, p.n);
}

if (process.argv[1] && path.resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
  const out = path.resolve(process.argv[2] || path.join(root, 'web', 'models', 'demo-saddle.obj'));
  const text = demoSaddleObj();
  fs.mkdirSync(path.dirname(out), { recursive: true });
  fs.writeFileSync(out, text);
  const { n } = SADDLE_PARAMS;
  console.log(`${path.relative(process.cwd(), out)}: ${(n + 1) ** 2} vertices, ${2 * n * n} faces, ${text.length} bytes`);
}
