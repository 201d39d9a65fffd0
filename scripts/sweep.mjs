#!/usr/bin/env node
// SPDX-License-Identifier: MIT
// The sweep of issue 25 at any size, for closing notes: voxel, geodesic and multidir on the shared
// closed models, on table5 and robot6-ur5, each program checked as the pipeline checks it
// (verify = warn, so the figures of a program that would be refused are there too). One JSON row
// per slice on stdout, all rows in OUT/rows.json. Not a test (tests/core/pipeline/sweep_test.cpp
// is, at 20 mm); at 40 mm the 54 slices take about 15 minutes on one core.
//
//   node scripts/sweep.mjs                     # 40 mm, every method and machine
//   FIT=20 METHODS=voxel MACHINES=table5 ONLY=kitten-ply,topopt SET="voxel.max_thickness_ratio=0" \
//     OUT=/tmp/sweep node scripts/sweep.mjs
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const CLI = process.env.CLI || path.join(ROOT, 'build/native/omnislice');
const MODELS = process.env.OMNISLICE_SHARED_MODELS || path.resolve(ROOT, '../shared/models');
// [name, file, placement arguments]: the closed models of ../shared/models/MANIFEST.md.
const models = [
  ['kitten-off', 'pymdp_kitten.off', ['--up', 'y']],
  ['kitten-ply', 'voxelmaam_kitten.ply', []],
  ['bunny-low', 'compas_bunny_closed_low_res.obj', []],
  ['branches70', 'compas_branches_70_closed_low_res.stl', []],
  ['coin', 'compas_overhang_coin_closed_low_res.stl', []],
  ['fertility', 'nestedcages_fertility.off', []],
  ['yoga', 'reinforcedfdm_YogaNew.tet', ['--up', 'y']],
  ['bunnyhead', 'reinforcedfdm_bunnyhead.tet', []],
  ['topopt', 'reinforcedfdm_topopt_new.tet', []],
];
const list = (v, d) => (v || d).split(',').filter(Boolean);
const methods = list(process.env.METHODS, 'voxel,geodesic,multidir');
const machines = list(process.env.MACHINES, 'table5,robot6-ur5');
const only = process.env.ONLY ? list(process.env.ONLY) : null;
const fit = process.env.FIT || '40';
const extra = (process.env.SET || '').split(' ').filter(Boolean).flatMap((s) => ['--set', s]);
const out = process.env.OUT || fs.mkdtempSync(path.join(os.tmpdir(), 'omnislice-sweep-'));
fs.mkdirSync(out, { recursive: true });
if (!fs.existsSync(CLI)) throw new Error(`no native CLI at ${CLI} (bash scripts/build.sh native)`);
if (!fs.existsSync(MODELS)) throw new Error(`no shared models at ${MODELS}`);

const round = (x, d = 4) => (Number.isFinite(x) ? Number(x.toFixed(d)) : x);
const rows = [];
for (const [name, file, placement] of models) {
  if (only && !only.includes(name)) continue;
  for (const method of methods) {
    for (const machine of machines) {
      const base = path.join(out, `${name}-${method}-${machine}`);
      const args = ['slice', path.join(MODELS, file), '-o', `${base}.prog`, '--report', `${base}.json`,
        '--method', method, '--machine', machine, '--fit-mm', fit, '--set', 'verify=warn', ...placement, ...extra];
      const row = { name, method, machine };
      const t0 = Date.now();
      try {
        execFileSync(CLI, args, { stdio: ['ignore', 'pipe', 'pipe'] });
        const r = JSON.parse(fs.readFileSync(`${base}.json`, 'utf8'));
        const v = r.verify;
        Object.assign(row, {
          s: (Date.now() - t0) / 1000, h: round(r.estimated_time_s / 3600, 2), layers: r.layers,
          inside: round(v.inside), cov: round(v.coverage), reached: round(v.surface_reached), sup: round(v.supported),
          coll: v.collisions,
          left: round(v.left_out_mm, 1), lim: v.limits, sound: v.sound,
          // Issue 33's motion figures: total rotary motion (deg; joint radians on robot6) and
          // the share of moves an axis or joint limits.
          rot: Math.round(r.motion.pose_cost), axis_limited: round(r.motion.feed_limited_moves / Math.max(1, r.motion.machine_moves), 3),
        });
        const bed = (r.warnings || []).find((w) => w.code === 'bead_on_platform');
        if (bed) row.bed_mm = Number(bed.message.split(' mm')[0]);
        if (r.voxel) Object.assign(row, { partial: r.voxel.thickness.partial_layers, reordered: r.voxel.reordered_paths });
        if (r.geodesic) Object.assign(row, { reordered: r.geodesic.reordered_paths, near_ideal: r.geodesic.near_ideal_paths });
        if (v.attempts && v.attempts.length) row.made_again = v.attempts.map((a) => `${a.settings}:${a.sound ? 'sound' : 'not'}`).join(' ');
      } catch (e) {
        row.error = String(e.stderr || e.message).split('\n')[0].slice(0, 200);
      }
      rows.push(row);
      console.log(JSON.stringify(row));
    }
  }
}
fs.writeFileSync(path.join(out, 'rows.json'), `${JSON.stringify(rows, null, 1)}\n`);
