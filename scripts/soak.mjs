#!/usr/bin/env node
// SPDX-License-Identifier: MIT
// npm run soak [-- JOBS]: JOBS slices (default 200) of every method, round robin, in ONE slicer
// worker of the page's engine (workers/engine.js) in headless Chromium, against the served wasm
// module (build/wasm). After every job it asks the worker for its memory (slicer.stats()).
//
// Passes when: every method slices (no job fails, none is refused), the worker is never replaced,
// each method gives the same program bytes on every run (its header's timestamp masked: no state
// leaks from one job into the next), and the memory malloc holds after the last job is at most
// 5 % above what it held after the first two rounds (12 jobs: the first jobs fill caches and grow
// the heap once). Prints one line per
// tenth of the run and a JSON summary (the heap curve: usedBytes and heapBytes after every
// tenth); exits non-zero when any of the above fails.
import { browserUnavailable, openPage } from '../tests/js/browser.mjs';

const perMethod = Number(process.argv[2] ?? process.env.SOAK_JOBS ?? 200);
if (!Number.isInteger(perMethod) || perMethod < 11) {
  console.error('soak: JOBS must be an integer >= 11 (jobs of every method)');
  process.exit(2);
}
const why = await browserUnavailable();
if (why) {
  console.error(`soak: ${why}`);
  process.exit(1);
}

// The jobs: small parts so 200 of each take minutes, every machine kind the methods print on.
const JOBS = [
  { method: 'planar', mesh: 'bracket', settings: { method: 'planar', machine: 'cartesian3', layer_height: 0.3 } },
  { method: 'multidir', mesh: 'bracket', settings: { method: 'multidir', machine: 'table5', layer_height: 0.3 } },
  { method: 'voxel', mesh: 'bracket', settings: { method: 'voxel', machine: 'table5', fit_mm: 16 } },
  { method: 'geodesic', mesh: 'bracket', settings: { method: 'geodesic', machine: 'robot6-ur5', fit_mm: 16 } },
  { method: 'surface', mesh: 'saddle', settings: { method: 'surface', machine: 'table5', layer_height: 0.3 } },
  // A part of 100,000 triangles: its slices grow the heap past the initial 64 MiB, so the heap's
  // own size is watched too.
  { method: 'planar-100k', mesh: 'torus', settings: { method: 'planar', machine: 'cartesian3', layer_height: 0.3 } },
];

const env = await openPage('/tests/js/fixtures/worker-harness.html');
const { page } = env;
let status = 0;
try {
  await page.waitForFunction(() => window.harnessReady === true, null, { timeout: 60000 });
  const total = perMethod * JOBS.length;
  await page.exposeFunction('soakLine', (line) => console.log(line));
  const run = await page.evaluate(async ({ jobs, total }) => {
    const meshes = await import('/tests/js/fixtures/meshes.js');
    const slicer = await window.engine.createSlicer({ workers: 1 });
    const ids = {
      bracket: (await slicer.loadMesh('bracket.stl', meshes.lBracketStl(10))).meshId,
      saddle: (await slicer.loadMesh('saddle.obj', new TextEncoder().encode(meshes.saddleObj(20, 10, 24)))).meshId,
      torus: (await slicer.loadMesh('torus.stl', meshes.torusStl(30, 10, 400, 125))).meshId,
    };
    const hex = (buf) => [...new Uint8Array(buf)].map((b) => b.toString(16).padStart(2, '0')).join('');
    const curve = [];
    const outcomes = {};  // method -> {outcome|digest -> count}
    const ms = {};
    const failures = [];
    const t0 = performance.now();
    for (let k = 0; k < total; ++k) {
      const job = jobs[k % jobs.length];
      const start = performance.now();
      let outcome;
      try {
        const r = await slicer.slice(ids[job.mesh], job.settings);
        // The header's timestamp masked: the only part that depends on the clock.
        const text = r.program.replace(/\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ/, 'TIMESTAMP');
        outcome = `ok ${hex(await crypto.subtle.digest('SHA-256', new TextEncoder().encode(text))).slice(0, 16)}`;
      } catch (e) {
        outcome = `error ${e.code}`;
        if (e.code === 'internal' || e.code === 'worker_failed') failures.push(`job ${k} ${job.method}: ${e.code}: ${e.message}`);
      }
      (ms[job.method] ||= []).push(performance.now() - start);
      const o = (outcomes[job.method] ||= {});
      o[outcome] = (o[outcome] || 0) + 1;
      const s = await slicer.stats();
      curve.push({ job: k + 1, usedBytes: s.usedBytes, heapBytes: s.heapBytes, workersStarted: s.workersStarted });
      if ((k + 1) % Math.max(1, Math.round(total / 10)) === 0 || k + 1 === total) {
        window.soakLine(`soak: ${k + 1}/${total} jobs, ${((performance.now() - t0) / 1000).toFixed(0)} s, ` +
          `malloc ${(s.usedBytes / 2 ** 20).toFixed(1)} MiB, heap ${(s.heapBytes / 2 ** 20).toFixed(0)} MiB, ` +
          `worker jobs ${s.jobs}, workers started ${s.workersStarted}`);
      }
    }
    slicer.dispose();
    return { curve, outcomes, ms, failures, seconds: (performance.now() - t0) / 1000 };
  }, { jobs: JOBS, total });

  const at = (n) => run.curve[n - 1];
  const base = at(JOBS.length * 2);  // after two rounds of the methods (the 12th job)
  const last = run.curve.at(-1);
  const growth = last.usedBytes / base.usedBytes - 1;
  const tenth = Math.max(1, Math.round(run.curve.length / 10));
  const median = (a) => [...a].sort((x, y) => x - y)[Math.floor(a.length / 2)];
  const summary = {
    jobs: run.curve.length,
    per_method: perMethod,
    seconds: Math.round(run.seconds),
    outcomes: run.outcomes,
    median_ms: Object.fromEntries(Object.entries(run.ms).map(([m, a]) => [m, Math.round(median(a))])),
    baseline_job: base.job,
    used_bytes_baseline: base.usedBytes,
    used_bytes_last: last.usedBytes,
    used_growth_pct: Number((100 * growth).toFixed(2)),
    heap_bytes_baseline: base.heapBytes,
    heap_bytes_last: last.heapBytes,
    heap_growth_pct: Number((100 * (last.heapBytes / base.heapBytes - 1)).toFixed(2)),
    workers_started: last.workersStarted,
    curve: run.curve.filter((c, i) => i === base.job - 1 || (i + 1) % tenth === 0)
      .map((c) => ({ job: c.job, used_mib: Number((c.usedBytes / 2 ** 20).toFixed(2)), heap_mib: c.heapBytes / 2 ** 20 })),
    failures: run.failures,
  };
  console.log(JSON.stringify(summary, null, 2));
  const problems = [];
  if (run.failures.length) problems.push(`${run.failures.length} jobs failed`);
  if (last.workersStarted !== 1) problems.push(`the worker was replaced ${last.workersStarted - 1} times`);
  for (const [m, o] of Object.entries(run.outcomes)) {
    if (Object.keys(o).length !== 1) problems.push(`${m}: ${Object.keys(o).length} different outcomes over its runs`);
    else if (!Object.keys(o)[0].startsWith('ok')) problems.push(`${m} did not slice (${Object.keys(o)[0]}): the soak does not exercise it`);
  }
  if (growth > 0.05) problems.push(`malloc grew ${(100 * growth).toFixed(1)} % after job ${base.job} (limit 5 %)`);
  const heapGrowth = last.heapBytes / base.heapBytes - 1;
  if (heapGrowth > 0.05) problems.push(`the wasm heap grew ${(100 * heapGrowth).toFixed(1)} % after job ${base.job} (limit 5 %)`);
  console.log(`soak: ${summary.jobs} jobs in ${summary.seconds} s, malloc ${summary.used_growth_pct >= 0 ? '+' : ''}` +
    `${summary.used_growth_pct} % after job ${base.job}, heap ${summary.heap_growth_pct} %, ` +
    `${problems.length ? `FAILED: ${problems.join('; ')}` : 'passed'}`);
  if (problems.length) status = 1;
} catch (e) {
  console.error(`soak: ${e.stack || e}`);
  status = 1;
} finally {
  await env.close();
}
process.exit(status);
