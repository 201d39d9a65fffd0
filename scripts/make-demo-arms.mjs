// SPDX-License-Identifier: MIT
// Generates the page's first demo: a post with three arms reaching out 20 degrees above the
// horizontal in three directions at three heights (one closed, outward-oriented OBJ mesh). It is
// made to show what multi-axis printing buys: planar layers print each arm's underside over air
// (70 degrees from vertical: supports under all three), while a machine with a tilting table
// prints each arm along its own axis, without supports. The page opens it on table5 with
// method = auto, so the first visit compares planar with supports against the multi-axis methods.
//
// The solid is the same implicit construction as the tree (scripts/make-demo-tree.mjs: a smooth
// union of capsules, cut flat at z = 0, marching tetrahedra on a regular grid), so the mesh is a
// closed 2-manifold by construction. The arms' end points are written out as decimals (computed
// once from 16 mm long arms at 20 degrees elevation, azimuths 0, 120 and 240 degrees) so the
// bytes depend on no trigonometric function (tests/js/demo-tree.test.mjs checks the committed file).
//
// Usage: node scripts/make-demo-arms.mjs [out.obj]   (default web/models/demo-arms.obj)
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { buildTreeMesh, toObj } from './make-demo-tree.mjs';

/** Parameters (mm): capsules [ax, ay, az, bx, by, bz, radius], blend width, grid step, decimals. */
export const ARMS_PARAMS = {
  capsules: [
    [0, 0, -6, 0, 0, 34, 4.5],                  // the post (below the platform: the cut makes the base)
    [0, 0, 10, 15.035, 0, 15.472, 3],           // arm towards +X, 20 degrees above the horizontal
    [0, 0, 18, -7.518, 13.021, 23.472, 3],      // towards 120 degrees
    [0, 0, 26, -7.518, -13.021, 31.472, 3],     // towards 240 degrees
  ],
  blend: 2.5,
  step: 1,
  decimals: 3,
};

const TITLE = 'omnislice demo: a post with three arms for multi-axis printing (scripts/make-demo-arms.mjs)';

/** The demo's OBJ text. */
export function demoArmsObj(p = ARMS_PARAMS) {
  return toObj(buildTreeMesh(p), p.decimals, TITLE);
}

if (process.argv[1] && path.resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
  const out = path.resolve(process.argv[2] || path.join(root, 'web', 'models', 'demo-arms.obj'));
  const text = demoArmsObj();
  fs.mkdirSync(path.dirname(out), { recursive: true });
  fs.writeFileSync(out, text);
  const faces = (text.match(/^f /gm) || []).length;
  console.log(`${path.relative(process.cwd(), out)}: ${faces} faces, ${text.length} bytes`);
}
