#!/usr/bin/env node
// SPDX-License-Identifier: MIT
// Native CLI vs wasm (in Node) per pipeline stage. Writes build/bench.json: a list of rows
// {case, stage, native_ms, wasm_ms, ratio} (ratio = wasm / native), prints them as a table and
// checks the targets: wasm/native <= 1.5 on planar slicing, 1M-triangle binary STL
// read+validate <= 1 s native, a 100k-triangle model sliced at 0.2 mm in <= 2 s in wasm; machines
// (issue 3): UR5 IK + pose continuity (the `motion` stage) <= 1 s per 100k samples in wasm, and
// verification of a >= 500k-move program <= 10 s in wasm; voxel method (issue 4): ~100k voxels
// <= 10 s in wasm, ~540k voxels <= 30 s in wasm within 1 GB of wasm memory, tool-paths for all
// layers of the Bunny (~100k voxels) <= 10 s in wasm; iso-planar paths (issue 5): theta* search
// (samples + feed field + 180 directions) on a 20k-vertex saddle <= 1 s in wasm, its paths
// <= 0.5 s in wasm; geodesic method (issue 6), a ~60k-tet model in wasm: tet meshing <= 2 s,
// field <= 0.5 s, IGDS extraction + remeshing <= 2 s, filling paths <= 3 s, mesh file to program
// <= 8 s; multidir (issue 7): the 5-DOF beam search on the 10k-triangle Kitten <= 1 s in wasm,
// the 4-DOF search over 180 axes <= 5 s. Each multidir case also gets a row (stage 'support')
// with the Omnislice figures and a `cura` object: CuraEngine 4.13's fixed-direction (+Z) print of
// the same placed model at the paper's Table I settings (scripts/cura-compare.mjs; installed by
// scripts/install-cura.sh, skipped with a message when it cannot be).
// Env: BENCH_REPS (default 3: best of N per stage), BENCH_SLICE_1M=1 (also slice the 1M mesh),
// BENCH_GEODESIC=0 / BENCH_MULTIDIR=0 skip those cases, BENCH_CURA=0 skips the CuraEngine
// comparison, BENCH_ONLY=text keeps only the cases whose name contains it, OMNISLICE_SHARED_MODELS
// the shared models folder (default ../shared/models), BENCH_REAL=1 adds each method on the Kitten
// at 100 mm and 0.2 mm layers (minutes).
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';
import { Worker } from 'node:worker_threads';
import { runAutoPool } from '../workers/auto-pool.js';
import { compareWithCura } from './cura-compare.mjs';
import { generateBenchModels } from './gen-bench-models.mjs';

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const CLI = process.env.OMNISLICE_CLI || path.join(ROOT, 'build/native/omnislice');
const WASM_DIR = process.env.OMNISLICE_WASM_DIR || path.join(ROOT, 'build/wasm');
// The shared test models (next to the repository; OMNISLICE_SHARED_MODELS for a worktree elsewhere).
const SHARED_MODELS = process.env.OMNISLICE_SHARED_MODELS || path.resolve(ROOT, '../shared/models');
const REPS = Math.max(1, Number(process.env.BENCH_REPS) || 3);
const STAGES = ['read', 'validate', 'place', 'voxelize', 'peeling', 'growth', 'layers', 'slice', 'toolpath',
  'isoplanar_samples', 'isoplanar_feed', 'isoplanar_direction', 'isoplanar_paths', 'isoplanar_benchmark',
  'tetmesh', 'field', 'igds', 'order', 'paths', 'decompose', 'clip', 'motion', 'program', 'verify', 'surfaces', 'spirals'];
const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'omnislice-bench-'));

for (const f of [CLI, path.join(WASM_DIR, 'omnislice.mjs')]) {
  if (!fs.existsSync(f)) {
    console.error(`[bench] missing ${f}: run scripts/build.sh first`);
    process.exit(1);
  }
}

const wrapper = await import(pathToFileURL(path.join(WASM_DIR, 'omnislice.js')).href);
let wasm = await wrapper.loadOmnislice({
  moduleUrl: pathToFileURL(path.join(WASM_DIR, 'omnislice.mjs')).href,
  wasmBinary: fs.readFileSync(path.join(WASM_DIR, 'omnislice.wasm')),
});

// Warm-up: V8 compiles wasm with a baseline tier first and optimises hot functions later; one
// small slice lets the optimised code be in place before anything is timed.
{
  const { torusStl } = await import('../tests/js/fixtures/meshes.js');
  wasm.slice(torusStl(20, 6, 200, 60), 'warmup.stl', { layer_height: 0.3 });
}

function setArgs(settings) {
  return Object.entries(settings).flatMap(([k, v]) => ['--set', `${k}=${v}`]);
}

// The native CLI's report of one slice (null when it fails).
function reportOf(file, settings) {
  const report = path.join(tmp, 'table-report.json');
  try {
    execFileSync(CLI, ['slice', file, '-o', path.join(tmp, 'table.gcode'), '--report', report, ...setArgs(settings)],
      { stdio: 'ignore' });
    return JSON.parse(fs.readFileSync(report, 'utf8'));
  } catch (e) {
    console.error(`[bench] ${path.basename(file)} ${JSON.stringify(settings)}: ${e.message}`);
    return null;
  }
}

// Every slice is timed to the end: the check before writing runs (verify = warn: its time is in
// timings_ms.verify) but a program it would refuse is still written, so a model one method cannot
// print soundly (the yoga on robot6, geodesic) does not stop the bench. One program per slice
// (verify_attempts = 1): an unsound one is not made again with the pipeline's remedies, so every
// case times the same work whatever the check finds (a remedied slice costs one more program for
// each remedy tried: README "verify").
// Natively on one thread (threads = 1), as the wasm build runs, unless a case says otherwise (the
// rows of issue 28's threads).
const timed = (settings) => ({ verify: 'warn', verify_attempts: 1, threads: 1, ...settings });

// Stage timings of one run: {stage: ms, total, wall}.
function nativeRun(mode, file, settings) {
  const t0 = performance.now();
  let timings;
  if (mode === 'slice') {
    const report = path.join(tmp, 'report.json');
    execFileSync(CLI, ['slice', file, '-o', path.join(tmp, 'out.gcode'), '--report', report,
      ...setArgs(timed(settings))], { stdio: 'ignore' });
    const r = JSON.parse(fs.readFileSync(report, 'utf8'));
    // The voxel method's loops on the threads: its layers' surfaces (inside the layers stage) and
    // spirals (inside the toolpath stage).
    const v = r.voxel && r.voxel.timings_ms;
    timings = { ...r.timings_ms, ...(v ? { surfaces: v.surfaces, spirals: v.spirals } : {}) };
  } else {
    const out = execFileSync(CLI, ['info', file, ...setArgs(settings)],
      { encoding: 'utf8', maxBuffer: 64 << 20 });
    timings = JSON.parse(out).timings_ms;
  }
  return withTotals(timings, performance.now() - t0);
}

// total: engine time (timings_ms.total, else the sum of the stages); wall: around the whole call
// (native: process start, file read and G-code write included; wasm: marshalling included).
function withTotals(timings, wall) {
  const stages = STAGES.filter((k) => typeof timings[k] === 'number');
  const total = typeof timings.total === 'number' ? timings.total : stages.reduce((a, k) => a + timings[k], 0);
  return { ...timings, total, wall };
}

const robotSamples = {};  // per case label: tool-path samples through the UR5's IK
const voxelCounts = {};
function wasmRun(mode, bytes, name, settings, label) {
  const t0 = performance.now();
  const r = mode === 'slice' ? wasm.slice(bytes, name, timed(settings)) : wasm.info(bytes, name, settings);
  if (mode === 'slice' && settings.machine === 'robot6-ur5') robotSamples[label] = r.report.motion.samples;
  if (mode === 'slice' && r.report.voxel) voxelCounts[label] = r.report.voxel;
  if (mode === 'slice' && r.report.geodesic) geodesicCounts[label] = r.report.geodesic;
  if (mode === 'slice' && r.report.multidir) {
    multidirCounts[label] = r.report.multidir;
    const { layers, layer_height_mm, extrusion_mm, estimated_time_s } = r.report;
    multidirPrints[label] = { layers, layer_height_mm, extrusion_mm, estimated_time_s };
  }
  const wall = performance.now() - t0;
  const v = mode === 'slice' && r.report.voxel && r.report.voxel.timings_ms;
  const timings = mode === 'slice' ? { ...r.report.timings_ms, ...(v ? { surfaces: v.surfaces, spirals: v.spirals } : {}) } : r.info.timings_ms;
  if (mode === 'info' && r.info.repair) repairCounts[label] = r.info.repair;
  return withTotals(timings, wall);
}

// method = auto with its candidates in a pool of `size` worker threads, each with its own wasm
// instance (started and warmed up before the clock starts, as the page keeps its workers), the plan
// and the choice from this thread's instance: wall time, and the largest wasm heap of a worker.
let poolHeapBytes = null;
async function wasmPoolRun(bytes, name, settings, size) {
  const workers = [];
  for (let i = 0; i < size; i++) {
    const w = new Worker(new URL('./bench-pool-worker.mjs', import.meta.url), { workerData: { wasmDir: WASM_DIR } });
    await new Promise((resolve, reject) => { w.once('message', resolve); w.once('error', reject); });
    workers.push(w);
  }
  try {
    const t0 = performance.now();
    const s = timed(settings);
    const plan = wasm.autoPlan(bytes, name, s);
    let nextId = 1;
    const run = (lane, k, candidateSettings) => new Promise((resolve, reject) => {
      const id = nextId++;
      const w = workers[lane];
      const onMessage = (msg) => {
        if (msg.id !== id) return;
        w.off('message', onMessage);
        poolHeapBytes = Math.max(poolHeapBytes || 0, msg.heapBytes || 0);
        if (msg.error) reject(new wrapper.OmnisliceError(msg.error.code, msg.error.message));
        else resolve({ report: msg.report });
      };
      w.on('message', onMessage);
      w.postMessage({ id, bytes, name, settings: candidateSettings });
    });
    const { decision, result } = await runAutoPool({
      plan, settings: s, size, run, choose: async (c) => wasm.autoChoose(s, c),
    });
    const wall = performance.now() - t0;
    if (decision.chosen < 0) throw new Error(`auto in a pool: ${decision.message}`);
    console.error(`[bench] auto in a pool of ${size}: ${decision.auto.reason}`);
    return withTotals({ ...result.report.timings_ms, auto: wall }, wall);
  } finally {
    for (const w of workers) await w.terminate();
  }
}

// Best (minimum) of REPS runs, per stage.
function best(run, reps = REPS) {
  let out = null;
  for (let i = 0; i < reps; ++i) {
    const t = run();
    if (!out) out = { ...t };
    else for (const k of Object.keys(t)) out[k] = Math.min(out[k], t[k]);
  }
  return out;
}

const models = generateBenchModels(path.join(ROOT, 'build/bench'));
// Issue 26: read + validate + repair (repair = auto) of a 1M-triangle sphere with 1,000 holes.
const REPAIR_1M = 'sphere-1m 1000 holes read+repair';
const UNION_100K = 'spheres 2x50k overlapping read+unite';
const repairCounts = {};
const cases = [
  { case: 'torus-100k slice 0.2mm', mode: 'slice', file: models['torus-100k.stl'], settings: { layer_height: 0.2 } },
  { case: 'sphere-1m read+validate', mode: 'info', file: models['sphere-1m.stl'], settings: {} },
  { case: REPAIR_1M, mode: 'info', file: models['sphere-1m-holes.stl'], settings: {} },
  // Issue 26: two overlapping 50k-triangle spheres united (CGAL corefinement) in validate.
  { case: UNION_100K, mode: 'info', file: models['spheres-2x50k-overlap.stl'], settings: {} },
  // Issue 26: a 100k-triangle box tessellated face by face: T-junctions zipped; with the cracks
  // opened, rebuilt from inside/outside samples.
  { case: 'box 100k T-junctions read+zip', mode: 'info', file: models['box-100k-tjunctions.stl'], settings: {} },
  { case: 'box 100k cracks read+rebuild', mode: 'info', file: models['box-100k-cracks.stl'], settings: {} },
];
if (process.env.BENCH_SLICE_1M === '1') {
  cases.push({ case: 'sphere-1m slice 0.2mm', mode: 'slice', file: models['sphere-1m.stl'], settings: { layer_height: 0.2 } });
}
// UR5: ~100k tool-path samples through IK (30 free-rotation samples x 8 branches) + pose continuity.
cases.push({ case: 'torus-100k robot6-ur5 0.4mm', mode: 'slice', file: models['torus-100k.stl'],
  settings: { layer_height: 0.4, machine: 'robot6-ur5' } });
const bunny = path.join(SHARED_MODELS, 'compas_bunny_closed_high_res.stl');
if (fs.existsSync(bunny)) {
  cases.push({ case: 'bunny-70k (shared) slice 0.2mm fit 100', mode: 'slice', file: bunny,
    settings: { layer_height: 0.2, fit_mm: 100 } });
}

// Voxel method (paper 001) on the shared Bunny: fit sizes chosen for ~100k and ~540k voxels at
// w = 0.8 x 0.5 mm nozzle = 0.4 mm (the paper's Bunny had 97.5k voxels, its Armadillo 540.7k).
const VOXEL_100K = 'bunny voxel ~100k voxels (table5)';
const VOXEL_540K = 'bunny voxel ~540k voxels (table5)';
if (fs.existsSync(bunny)) {
  const voxel = { method: 'voxel', machine: 'table5', nozzle_diameter: 0.5, layer_height: 0.4, line_width: 0.55 };
  cases.push({ case: VOXEL_100K, mode: 'slice', file: bunny, settings: { ...voxel, fit_mm: Number(process.env.BENCH_VOXEL_FIT_100K) || 30.5 } });
  if (process.env.BENCH_VOXEL_540K !== '0') {
    cases.push({ case: VOXEL_540K, mode: 'slice', file: bunny, settings: { ...voxel, fit_mm: Number(process.env.BENCH_VOXEL_FIT_540K) || 54.5 }, freshModule: true, reps: 1 });
  }
}

// Iso-planar paths (paper 003) on a 20k-vertex saddle z = (x^2 - y^2) / 100 over 75 x 75 mm (the
// paper's S1 size), printed with method surface on the UR5 (Table 1: s = 1 mm, h = 0.75 mm).
const SADDLE = 'saddle 20k vertices surface (robot6-ur5)';
{
  const { saddleObj } = await import('../tests/js/fixtures/meshes.js');
  const file = path.join(ROOT, 'build/bench/saddle-20k.obj');
  const text = saddleObj(100, 37.5, 141);
  if (!fs.existsSync(file) || fs.readFileSync(file, 'utf8') !== text) fs.writeFileSync(file, text);
  cases.push({ case: SADDLE, mode: 'slice', file, settings: { method: 'surface', machine: 'robot6-ur5',
    nozzle_diameter: 1, layer_height: 0.75, line_width: 1.125, 'isoplanar.benchmark': false } });
}

// Geodesic method (paper 002): the shared Bunny meshed into ~60k tets by Omnislice (the paper's
// Bunny had 61,579 HyperMesh tets), 0.6 mm interval as the paper's Section 4.1; and the shared
// Yoga tet model (52k tets from the file).
const GEO_BUNNY = 'bunny geodesic ~60k tets (table5)';
const GEO_YOGA = 'yoga.tet geodesic 52k tets (robot6)';
const geo = { method: 'geodesic', nozzle_diameter: 0.8, layer_height: 0.6, line_width: 0.8 };
if (fs.existsSync(bunny) && process.env.BENCH_GEODESIC !== '0') {
  cases.push({ case: GEO_BUNNY, mode: 'slice', file: bunny, settings: { ...geo, machine: 'table5', fit_mm: 60, 'geodesic.target_tets': 60000 }, reps: 1 });
  const yoga = path.join(SHARED_MODELS, 'reinforcedfdm_YogaNew.tet');
  if (fs.existsSync(yoga)) {
    cases.push({ case: GEO_YOGA, mode: 'slice', file: yoga, settings: { ...geo, machine: 'robot6-ur5', up: 'y', fit_mm: 100 }, reps: 1 });
  }
}
const geodesicCounts = {};
// Multi-directional decomposition (issue 7, paper 000) on the paper's 10k-triangle Kitten: the
// full 5-DOF beam search (robot6 reaches the full-size part) and the 4-DOF search over 180 axes.
const MD_5DOF = 'kitten multidir 5-DOF beam (robot6)';
const MD_4DOF = 'kitten multidir 4-DOF 180 axes (rotary4)';
const kitten = path.join(SHARED_MODELS, 'pymdp_kitten.off');
const multidirCounts = {};
const multidirPrints = {};  // per multidir case: the program's layers, extrusion and time estimate
if (fs.existsSync(kitten) && process.env.BENCH_MULTIDIR !== '0') {
  const md = { method: 'multidir', up: 'y', layer_height: 0.3 };
  cases.push({ case: MD_5DOF, mode: 'slice', file: kitten, settings: { ...md, machine: 'robot6-ur5' }, reps: 1 });
  cases.push({ case: MD_4DOF, mode: 'slice', file: kitten, settings: { ...md, machine: 'rotary4', 'multidir.axis_search': 180 }, reps: 1 });
}

// Issue 28 item 1: method = auto on the Kitten at 60 mm on table5 against each method alone (the
// target: auto <= 1.3 x the slowest single method, in wasm).
const AUTO_CASE = 'kitten-60 table5 auto';
const AUTO_POOL_CASE = 'kitten-60 table5 auto, 2 threads / 2 workers';
const VOXEL_THREADS_CASE = 'kitten-60 table5 voxel, 2 threads';
const AUTO_SINGLES = ['planar', 'multidir', 'geodesic', 'voxel'].map((m) => [m, `kitten-60 table5 ${m} alone`]);
if (fs.existsSync(kitten) && process.env.BENCH_AUTO !== '0') {
  const k60 = { up: 'y', fit_mm: 60, machine: 'table5' };
  cases.push({ case: AUTO_CASE, mode: 'slice', file: kitten, settings: { ...k60, method: 'auto' }, reps: 1 });
  // Issue 28 item 2: the candidates side by side, natively in threads (threads = 2) and in wasm in
  // a pool of 2 worker threads with a wasm instance each (workers/auto-pool.js, as the page runs them).
  cases.push({ case: AUTO_POOL_CASE, mode: 'auto-pool', file: kitten, settings: { ...k60, method: 'auto', threads: 2 }, reps: 1 });
  for (const [m, name] of AUTO_SINGLES) {
    cases.push({ case: name, mode: 'slice', file: kitten, settings: { ...k60, method: m, verify: 'warn' }, reps: 1 });
  }
  // Issue 28 item 2, the loops inside a method natively on 2 threads (wasm has no threads): the
  // voxel method's layers and its spirals (the toolpath stage), against voxel alone on one.
  cases.push({ case: VOXEL_THREADS_CASE, mode: 'slice', file: kitten, settings: { ...k60, method: 'voxel', verify: 'warn', threads: 2 }, reps: 1, nativeOnly: true });
}

// Issue 28, real sizes: each method on the Kitten at 100 mm with 0.2 mm layers on table5 (target:
// <= 60 s each in wasm). Long (minutes natively and in wasm): only with BENCH_REAL=1. A method that
// refuses the size (e.g. voxel.max_voxels) is reported with its error.
const REAL_CASES = ['planar', 'multidir', 'geodesic', 'voxel'].map((m) => [m, `kitten-100 0.2mm table5 ${m}`]);
if (fs.existsSync(kitten) && process.env.BENCH_REAL === '1') {
  for (const [m, name] of REAL_CASES) {
    cases.push({ case: name, mode: 'slice', file: kitten, settings: { up: 'y', fit_mm: 100, layer_height: 0.2, machine: 'table5', method: m }, reps: 1, mayFail: true });
  }
}

if (process.env.BENCH_ONLY) {
  const keep = cases.filter((c) => c.case.includes(process.env.BENCH_ONLY));
  cases.length = 0;
  cases.push(...keep);
}
const rows = [];
const failures = [];  // [case, error] of the cases that may fail (BENCH_REAL)
let voxelMemoryBytes = null;
for (const c of cases) {
  const bytes = fs.readFileSync(c.file);
  console.error(`[bench] ${c.case}: native...`);
  let n;
  try {
    n = best(() => nativeRun(c.mode === 'auto-pool' ? 'slice' : c.mode, c.file, c.settings), c.reps);
  } catch (e) {
    if (!c.mayFail) throw e;
    // The CLI's own line (`error: <code>: <message>`), run again to read it (stdio is ignored above).
    let why = String(e.message).trim().split('\n')[0];
    try {
      execFileSync(CLI, ['slice', c.file, '-o', path.join(tmp, 'refused.gcode'), ...setArgs(timed(c.settings))], { stdio: ['ignore', 'ignore', 'pipe'] });
    } catch (again) {
      why = String(again.stderr || why).trim().split('\n').pop();
    }
    console.error(`[bench] ${c.case}: ${why}`);
    failures.push([c.case, why]);
    continue;
  }
  if (!c.nativeOnly) console.error(`[bench] ${c.case}: wasm...`);
  let w;
  if (c.nativeOnly) {
    w = {};
  } else if (c.mode === 'auto-pool') {
    w = await wasmPoolRun(bytes, path.basename(c.file), c.settings, 2);
  } else if (c.freshModule) {
    // A fresh instance so its memory size is this case's peak (wasm memory never shrinks).
    const saved = wasm;
    wasm = await wrapper.loadOmnislice({
      moduleUrl: pathToFileURL(path.join(WASM_DIR, 'omnislice.mjs')).href,
      wasmBinary: fs.readFileSync(path.join(WASM_DIR, 'omnislice.wasm')),
    });
    w = best(() => wasmRun(c.mode, bytes, path.basename(c.file), c.settings, c.case), c.reps);
    const heap = wasm.raw.HEAPU8 || (wasm.raw.wasmMemory && new Uint8Array(wasm.raw.wasmMemory.buffer));
    voxelMemoryBytes = heap ? heap.buffer.byteLength : null;
    wasm = saved;
  } else {
    try {
      w = best(() => wasmRun(c.mode, bytes, path.basename(c.file), c.settings, c.case), c.reps);
    } catch (e) {
      if (!c.mayFail) throw e;
      console.error(`[bench] ${c.case} in wasm: ${e.code}: ${e.message}`);
      failures.push([c.case, `in wasm ${e.code}: ${e.message}`]);
      w = {};
      if (e.fatal) {
        wasm = await wrapper.loadOmnislice({
          moduleUrl: pathToFileURL(path.join(WASM_DIR, 'omnislice.mjs')).href,
          wasmBinary: fs.readFileSync(path.join(WASM_DIR, 'omnislice.wasm')),
        });
      }
    }
  }
  for (const stage of [...STAGES, 'total', 'wall']) {
    if (n[stage] === undefined && w[stage] === undefined) continue;
    const native_ms = n[stage] ?? null;
    const wasm_ms = w[stage] ?? null;
    const ratio = native_ms > 0 && wasm_ms !== null ? wasm_ms / native_ms : null;
    rows.push({ case: c.case, stage, native_ms, wasm_ms, ratio });
  }
}

// CuraEngine on each multidir case's model, placed as the case places it, along the fixed +Z
// direction (paper 000, Table I: "Fixed Dir." support volume and printing time with Cura at
// 0.4 mm layers and 20% grid infill), once per model and placement.
const curaRuns = {};
const curaSkip = process.env.BENCH_CURA === '0' ? 'BENCH_CURA=0' : null;
for (const c of cases.filter((k) => k.settings.method === 'multidir')) {
  const placement = { up: c.settings.up, scale: c.settings.scale, fitMm: c.settings.fit_mm };
  const key = JSON.stringify([c.file, placement]);
  if (!(key in curaRuns)) {
    if (curaSkip) curaRuns[key] = { skipped: curaSkip };
    else {
      console.error(`[bench] ${path.basename(c.file)}: CuraEngine fixed direction, with and without supports...`);
      try {
        curaRuns[key] = compareWithCura(c.file, placement);
      } catch (e) {
        curaRuns[key] = { skipped: `CuraEngine run failed: ${e.message}` };
      }
      if (curaRuns[key].skipped) console.error(`[bench] Cura comparison skipped: ${curaRuns[key].skipped}`);
    }
  }
  // Omnislice at the same Table I settings (0.4 mm layers, 20 % grid infill): the fixed direction
  // (planar, projected supports along +Z) and this case's decomposition with projected supports.
  const tableI = { layer_height: 0.4, infill: 20, up: c.settings.up };
  if (c.settings.fit_mm) tableI.fit_mm = c.settings.fit_mm;
  const omniFixed = reportOf(c.file, { ...tableI, machine: 'cartesian3', support: 'projected' });
  const omniMulti = reportOf(c.file, { ...c.settings, ...tableI });
  const table = {
    settings: tableI,
    fixed_dir: omniFixed && { support_volume_mm3: omniFixed.support?.printed_volume_mm3 ?? 0,
      estimated_time_s: omniFixed.estimated_time_s, layers: omniFixed.layers },
    multi_dir: omniMulti && { support_volume_mm3: omniMulti.multidir?.support_volume_mm3 ?? 0,
      estimated_time_s: omniMulti.estimated_time_s, layers: omniMulti.layers, part_count: omniMulti.multidir?.part_count,
      J_G_after: omniMulti.multidir?.J_G_after },
  };
  const m = multidirCounts[c.case];
  const omnislice = m ? {
    J_G_before: m.J_G_before, J_G_after: m.J_G_after, part_count: m.part_count,
    supports_generated: m.supports_generated, support_volume_mm3: m.support_volume_mm3, ...multidirPrints[c.case],
  } : null;
  rows.push({ case: c.case, stage: 'support', native_ms: null, wasm_ms: null, ratio: null, omnislice, table_i: table,
    cura: curaRuns[key] });
}

// Verification of a large program (~500k moves; the torus scaled to 150 mm so the coverage grid
// at 0.2 mm stays within its cap): native CLI wall vs wasm call.
const verifyCase = 'torus-100k fit 150 verify 0.2mm program';
{
  const file = models['torus-100k.stl'];
  const program = path.join(tmp, 'big.gcode');
  const report = path.join(tmp, 'big.json');
  execFileSync(CLI, ['slice', file, '-o', program, '--report', report, '--fit-mm', '150'], { stdio: 'ignore' });
  const moves = JSON.parse(fs.readFileSync(report, 'utf8')).moves;
  const text = fs.readFileSync(program, 'utf8');
  const meshBytes = fs.readFileSync(file);
  console.error(`[bench] ${verifyCase} (${moves} moves): native...`);
  let native_ms = Infinity, wasm_ms = Infinity;
  for (let i = 0; i < REPS; ++i) {
    const t0 = performance.now();
    execFileSync(CLI, ['verify', program, '--mesh', file], { stdio: 'ignore' });
    native_ms = Math.min(native_ms, performance.now() - t0);
  }
  console.error(`[bench] ${verifyCase}: wasm...`);
  for (let i = 0; i < REPS; ++i) {
    const t0 = performance.now();
    wasm.verify(text, meshBytes, 'torus-100k.stl');
    wasm_ms = Math.min(wasm_ms, performance.now() - t0);
  }
  rows.push({ case: verifyCase, stage: 'verify', native_ms, wasm_ms, ratio: wasm_ms / native_ms, moves });
}

// Planar against CuraEngine (issue 27): the shared Kitten at 60 mm, both at Cura's defaults as
// CuraEngine reads them (0.4 mm layers and lines, 2 walls, 2 top/bottom layers, 20 % grid; walls
// and skin 30 mm/s, infill 60, travel 120; its time estimate plans at 9000 mm/s^2 with a 20 mm/s
// jerk, which for a right angle is a junction deviation of 20^2 (1 - s) / (9000 s) = 0.0184 mm, s =
// sin 45 deg). Slicing wall time of the native CLI against CuraEngine's (no supports); the
// estimated print times side by side, and Omnislice's own at its defaults (1500 mm/s^2, 0.013 mm).
const CURA_PLANAR = 'kitten-60 planar vs CuraEngine';
const planarCura = { case: CURA_PLANAR, stage: 'cura', native_ms: null, wasm_ms: null, ratio: null };
if (!process.env.BENCH_ONLY || CURA_PLANAR.includes(process.env.BENCH_ONLY)) {
  const kitten = path.join(SHARED_MODELS, 'pymdp_kitten.off');
  const cura = curaSkip ? { skipped: curaSkip } : fs.existsSync(kitten) ? compareWithCura(kitten, { up: 'y', fitMm: 60 })
    : { skipped: `${kitten} missing` };
  if (cura.skipped) {
    planarCura.cura_planar = { skipped: cura.skipped };
  } else {
    const same = { up: 'y', fit_mm: 60, layer_height: 0.4, nozzle_diameter: 0.4, line_width: 0.4, walls: 2, infill: 20,
      infill_pattern: 'grid', top_layers: 2, bottom_layers: 2, print_speed: 30, outer_wall_speed: 30, infill_speed: 60,
      first_layer_speed: 30, travel_speed: 120, verify: 'off', support: 'none' };
    let native_ms = Infinity;
    for (let i = 0; i < REPS; ++i) {
      const t0 = performance.now();
      reportOf(kitten, { ...same, acceleration: 9000, junction_deviation: 0.0184 });
      native_ms = Math.min(native_ms, performance.now() - t0);
    }
    const curaKin = reportOf(kitten, { ...same, acceleration: 9000, junction_deviation: 0.0184 });
    const own = reportOf(kitten, same);
    const fromRest = reportOf(kitten, { ...same, junction_deviation: 0 });
    const w = cura.without_supports;
    planarCura.native_ms = native_ms;
    planarCura.cura_planar = {
      cura_ms: w.ms, slice_ratio: native_ms / w.ms,
      cura_estimate_s: w.print_time_s, cura_filament_mm: w.filament_mm,
      estimate_at_cura_kinematics_s: curaKin?.estimated_time_s, estimate_s: own?.estimated_time_s,
      estimate_every_move_from_rest_s: fromRest?.estimated_time_s, filament_mm: curaKin?.extrusion_mm,
      path_mm: curaKin?.path_mm, travel_mm: curaKin?.travel_mm,
    };
  }
  rows.push(planarCura);
}

const round = (v, d = 1) => (v === null || v === undefined ? null : Number(v.toFixed(d)));
const out = rows.map((r) => ({ ...r, native_ms: round(r.native_ms), wasm_ms: round(r.wasm_ms), ratio: round(r.ratio, 2) }));
fs.mkdirSync(path.join(ROOT, 'build'), { recursive: true });
fs.writeFileSync(path.join(ROOT, 'build/bench.json'), `${JSON.stringify(out, null, 2)}\n`);

const pad = (s, n) => String(s ?? '-').padEnd(n);
const padL = (s, n) => String(s ?? '-').padStart(n);
console.log(`${pad('case', 40)} ${pad('stage', 10)} ${padL('native ms', 10)} ${padL('wasm ms', 10)} ${padL('ratio', 6)}`);
for (const r of out) {
  console.log(`${pad(r.case, 40)} ${pad(r.stage, 10)} ${padL(r.native_ms, 10)} ${padL(r.wasm_ms, 10)} ${padL(r.ratio, 6)}`);
}

// Targets.
const get = (c, s) => out.find((r) => r.case === c && r.stage === s);
const checks = [];
const planar = get('torus-100k slice 0.2mm', 'slice');
if (planar) checks.push(['wasm/native on planar slicing (slice stage, torus-100k) <= 1.5', planar.ratio, planar.ratio <= 1.5]);
const planarTotal = get('torus-100k slice 0.2mm', 'total');
if (planarTotal) checks.push(['wasm/native total, torus-100k slice <= 1.5', planarTotal.ratio, planarTotal.ratio <= 1.5]);
const rv = ['read', 'validate'].map((s) => get('sphere-1m read+validate', s));
if (rv.every(Boolean)) {
  const ms = rv[0].native_ms + rv[1].native_ms;
  checks.push(['1M-triangle binary STL read+validate native <= 1000 ms', round(ms), ms <= 1000]);
}
const rr = ['read', 'validate'].map((s) => get(REPAIR_1M, s));
if (rr.every(Boolean) && repairCounts[REPAIR_1M]) {
  const ms = rr[0].wasm_ms + rr[1].wasm_ms;
  const r = repairCounts[REPAIR_1M];
  checks.push([`1M-triangle mesh with ${r.holes_filled} holes filled (largest ${round(r.largest_hole_mm)} mm), read+validate+repair in wasm <= 3000 ms`,
    round(ms), ms <= 3000]);
}
const planarWall = get('torus-100k slice 0.2mm', 'wall');
if (planarWall) checks.push(['100k-triangle slice at 0.2 mm in wasm (wall, marshalling included) <= 2000 ms', planarWall.wasm_ms, planarWall.wasm_ms <= 2000]);
const robotCase = 'torus-100k robot6-ur5 0.4mm';
const robotMotion = get(robotCase, 'motion');
if (robotMotion) {
  const samples = robotSamples[robotCase];
  const per100k = robotMotion.wasm_ms * 100000 / samples;
  checks.push([`UR5 IK + pose continuity in wasm per 100k samples (${samples} samples) <= 1000 ms`, round(per100k), per100k <= 1000]);
}
const verifyRow = get(verifyCase, 'verify');
if (verifyRow) checks.push([`verify a ${verifyRow.moves}-move program in wasm <= 10000 ms`, verifyRow.wasm_ms, verifyRow.wasm_ms <= 10000]);
for (const [label, limit, memory] of [[VOXEL_100K, 10000, false], [VOXEL_540K, 30000, true]]) {
  const row = get(label, 'total');
  const v = voxelCounts[label];
  if (!row || !v) continue;
  checks.push([`${label}: ${v.voxels} voxels, ${v.missed_voxels} missed, ${v.layers} layers, wasm total <= ${limit} ms`,
    row.wasm_ms, row.wasm_ms <= limit]);
  if (memory) {
    const mb = voxelMemoryBytes === null ? null : round(voxelMemoryBytes / 1048576);
    checks.push([`${label}: wasm memory <= 1024 MB`, mb, mb !== null && mb <= 1024]);
  }
}
const bunnyToolpath = get(VOXEL_100K, 'toolpath');
if (bunnyToolpath) checks.push([`tool-paths for all layers of the Bunny (${VOXEL_100K}) in wasm <= 10000 ms`, bunnyToolpath.wasm_ms, bunnyToolpath.wasm_ms <= 10000]);
{
  const st = ['isoplanar_samples', 'isoplanar_feed', 'isoplanar_direction'].map((k) => get(SADDLE, k));
  if (st.every(Boolean)) {
    const w = st.reduce((a, r) => a + r.wasm_ms, 0);
    const n = st.reduce((a, r) => a + r.native_ms, 0);
    checks.push([`theta* search on a 20k-vertex saddle, 180 directions, in wasm (native ${round(n)} ms) <= 1000 ms`, round(w), w <= 1000]);
  }
  const paths = get(SADDLE, 'isoplanar_paths');
  if (paths) checks.push([`iso-planar paths of the 20k-vertex saddle in wasm (native ${paths.native_ms} ms) <= 500 ms`, paths.wasm_ms, paths.wasm_ms <= 500]);
}
for (const label of [GEO_BUNNY, GEO_YOGA]) {
  const g = geodesicCounts[label];
  if (!g) continue;
  const what = `${label}: ${g.tets} tets, ${g.layers} layers, ${g.igds} IGDS`;
  const limits = label === GEO_BUNNY ? [['tetmesh', 2000], ['field', 500], ['igds', 2000], ['paths', 3000]]
    : [['field', 500], ['igds', 2000], ['paths', 3000]];
  for (const [stage, limit] of limits) {
    const row = get(label, stage);
    if (row) checks.push([`${what}: ${stage} in wasm (native ${row.native_ms} ms) <= ${limit} ms`, row.wasm_ms, row.wasm_ms <= limit]);
  }
  const total = get(label, 'total');
  if (total) checks.push([`${what}: mesh file to program in wasm (native ${total.native_ms} ms) <= 8000 ms`, total.wasm_ms, total.wasm_ms <= 8000]);
}
{
  const autoRow = get(AUTO_CASE, 'wall');
  const singles = AUTO_SINGLES.map(([, name]) => get(name, 'wall')).filter(Boolean);
  if (autoRow && singles.length === AUTO_SINGLES.length) {
    const slowest = (k) => Math.max(...singles.map((r) => r[k]));
    const ratio = autoRow.wasm_ms / slowest('wasm_ms');
    checks.push([`method = auto, kitten 60 mm on table5, in wasm ${round(autoRow.wasm_ms)} ms (native ${round(autoRow.native_ms)}) ` +
      `<= 1.3 x the slowest method alone (${round(slowest('wasm_ms'))} ms; native ${round(slowest('native_ms'))})`, round(ratio, 2), ratio <= 1.3]);
  }
}
{
  const poolRow = get(AUTO_POOL_CASE, 'wall');
  const singles = AUTO_SINGLES.map(([, name]) => get(name, 'wall')).filter(Boolean);
  if (poolRow && singles.length === AUTO_SINGLES.length) {
    const slowest = (k) => Math.max(...singles.map((r) => r[k]));
    const ratio = poolRow.wasm_ms / slowest('wasm_ms');
    checks.push([`method = auto in a pool of 2 wasm workers, kitten 60 mm on table5, ${round(poolRow.wasm_ms)} ms (native in 2 threads ` +
      `${round(poolRow.native_ms)}; largest worker heap ${poolHeapBytes ? round(poolHeapBytes / 2 ** 20) : '-'} MiB) ` +
      `<= 1.3 x the slowest method alone (${round(slowest('wasm_ms'))} ms; native ${round(slowest('native_ms'))})`, round(ratio, 2), ratio <= 1.3]);
  }
}
for (const stage of ['surfaces', 'spirals', 'layers', 'total']) {
  const one = get('kitten-60 table5 voxel alone', stage);
  const two = get(VOXEL_THREADS_CASE, stage);
  if (!one || !two || !(two.native_ms > 0)) continue;
  const speedup = one.native_ms / two.native_ms;
  const what = `voxel, kitten 60 mm on table5, natively: ${stage} on 2 threads ${round(two.native_ms)} ms against ${round(one.native_ms)} ms on one`;
  // The loops themselves (surfaces: the voxel layers' full and partial surfaces; spirals) are the
  // target; their stages and the total also hold work on one thread: shown, not a target.
  if (stage === 'layers' || stage === 'total') console.log(`\n${what}: speed-up ${round(speedup, 2)}`);
  else checks.push([`${what} (speed-up >= 1.7)`, round(speedup, 2), speedup >= 1.7]);
}
for (const [label, limit] of [[MD_5DOF, 1000], [MD_4DOF, 5000]]) {
  const m = multidirCounts[label];
  const row = get(label, 'decompose');
  if (!m || !row) continue;
  checks.push([`${label}: J_G ${round(m.J_G_before)} -> ${m.J_G_after.toFixed(3)} mm^2, ${m.part_count} parts: search in wasm (native ${row.native_ms} ms) <= ${limit} ms`,
    row.wasm_ms, row.wasm_ms <= limit]);
}
const hms = (s) => (typeof s === 'number' ? `${Math.floor(s / 3600)}h${String(Math.floor(s / 60) % 60).padStart(2, '0')}m` : '-');
const supportRows = out.filter((r) => r.cura);
if (supportRows.length) console.log('\nfixed direction (+Z) with CuraEngine vs multidir:');
for (const r of supportRows) {
  const c = r.cura, o = r.omnislice;
  const omni = o ? `Omnislice multidir: J_G ${round(o.J_G_before)} -> ${round(o.J_G_after, 3)} mm^2, ${o.part_count} parts, ` +
    `support ${round(o.support_volume_mm3)} mm^3${o.supports_generated ? '' : ' (supports not generated)'}, ` +
    `${o.layers} layers at ${o.layer_height_mm} mm, estimated ${hms(o.estimated_time_s)}` : 'no Omnislice report';
  if (c.skipped) console.log(`  ${r.case}: Cura skipped (${c.skipped}); ${omni}`);
  else {
    const w = c.without_supports;
    console.log(`  ${r.case}: ${c.version} +Z at ${c.settings.layer_height} mm, ${c.settings.infill_sparse_density}% grid: ` +
      `support ${round(c.support_volume_mm3)} mm^3 (${round(c.support_path_mm / 1000, 2)} m of path), model ${round(c.model_volume_mm3)} mm^3, ` +
      `${hms(c.print_time_s)} (${c.print_time_s} s), ${c.layers} layers; without supports ${hms(w.print_time_s)} (${w.print_time_s} s)`);
    console.log(`    ${omni}`);
  }
  const t = r.table_i;
  if (t && t.fixed_dir && t.multi_dir) {
    console.log(`    Omnislice at ${t.settings.layer_height} mm, ${t.settings.infill}% (Table I): fixed dir support ` +
      `${round(t.fixed_dir.support_volume_mm3)} mm^3, ${hms(t.fixed_dir.estimated_time_s)}; multi-dir support ` +
      `${round(t.multi_dir.support_volume_mm3)} mm^3, ${hms(t.multi_dir.estimated_time_s)} (${t.multi_dir.part_count} parts)`);
  }
}
const pc = out.find((r) => r.case === CURA_PLANAR);
if (pc && pc.cura_planar) {
  const c = pc.cura_planar;
  if (c.skipped) console.log(`\nplanar vs CuraEngine skipped (${c.skipped})`);
  else {
    console.log(`\nplanar vs CuraEngine (kitten 60 mm, Cura's defaults): slicing ${round(pc.native_ms)} ms vs ${round(c.cura_ms)} ms; ` +
      `estimated ${round(c.estimate_at_cura_kinematics_s)} s at Cura's kinematics vs Cura's ${c.cura_estimate_s} s ` +
      `(Omnislice defaults ${round(c.estimate_s)} s; every move from rest ${round(c.estimate_every_move_from_rest_s)} s); ` +
      `filament ${round(c.filament_mm)} vs ${round(c.cura_filament_mm)} mm`);
    checks.push(['planar slicing time / CuraEngine\'s (kitten 60 mm, native) < 1', round(c.slice_ratio, 2), c.slice_ratio < 1]);
    const er = c.estimate_at_cura_kinematics_s / c.cura_estimate_s;
    checks.push(['estimated time / CuraEngine\'s at its kinematics within 0.85..1.15', round(er, 3), er >= 0.85 && er <= 1.15]);
  }
}
for (const [, name] of REAL_CASES) {
  const row = get(name, 'wall');
  const failed = failures.find(([c]) => c === name);
  if (failed) console.log(`\n${name}: refused: ${failed[1]}${row ? ` (native ${round(row.native_ms)} ms)` : ''}`);
  else if (row) checks.push([`${name} in wasm (native ${round(row.native_ms)} ms) <= 60000 ms`, round(row.wasm_ms), row.wasm_ms <= 60000]);
}
console.log('\ntargets:');
for (const [what, value, ok] of checks) console.log(`  ${ok ? 'PASS' : 'MISS'}  ${what}: ${value}`);
console.log(`\nwrote ${path.join(ROOT, 'build/bench.json')}`);
fs.rmSync(tmp, { recursive: true, force: true });
