// SPDX-License-Identifier: MIT
// The worker protocol through the engine facade (workers/engine.js) in headless Chromium: real
// module workers, transfers, progress order, every search level of a multidir slice, cancel,
// error and crash recovery.
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { browserUnavailable, openPage } from './browser.mjs';
import { checkSearchLevels } from './search-levels.mjs';

const why = await browserUnavailable();
if (why && process.env.CI === 'true') throw new Error(`browser tests cannot run under CI: ${why}`);

describe('worker protocol (Chromium)', { skip: why ? `skipped: ${why}` : false }, () => {
  let env;
  let page;
  before(async () => {
    env = await openPage('/tests/js/fixtures/worker-harness.html');
    page = env.page;
    await page.waitForFunction(() => window.harnessReady === true, null, { timeout: 30000 });
    await page.evaluate(async () => {
      window.meshes = await import('/tests/js/fixtures/meshes.js');
      window.slicer = await window.engine.createSlicer({ workerUrl: '/tests/js/fixtures/spy-worker.js' });
    });
  });
  after(async () => {
    if (page) await page.evaluate(() => window.slicer && window.slicer.dispose());
    if (env) await env.close();
  });

  test('loadMesh returns info and the placed mesh; the bytes are transferred to the worker', async () => {
    const r = await page.evaluate(async () => {
      window.sentTransfers.length = 0;
      const bytes = window.meshes.torusStl(20, 6, 64, 24);
      const { meshId, info, mesh } = await window.slicer.loadMesh('torus.stl', bytes, { up: 'z' });
      window.torusId = meshId;
      const load = window.sentTransfers.find((s) => s.type === 'load');
      return {
        meshId, info, callerBytes: bytes.byteLength, load,
        positions: mesh.positions.constructor.name, indices: mesh.indices.constructor.name,
        nPositions: mesh.positions.length, nIndices: mesh.indices.length,
      };
    });
    assert.equal(typeof r.meshId, 'string');
    assert.equal(r.info.faces, 2 * 64 * 24);
    assert.equal(r.info.vertices, 64 * 24);
    assert.equal(r.info.closed, true);
    assert.equal(r.positions, 'Float32Array');
    assert.equal(r.indices, 'Uint32Array');
    assert.equal(r.nIndices, 3 * 2 * 64 * 24);
    assert.equal(r.nPositions, 3 * 64 * 24);
    assert.equal(r.callerBytes, 84 + 50 * 2 * 64 * 24, "the caller's buffer is not detached");
    assert.ok(r.load, 'a load request was posted');
    assert.deepEqual(r.load.before, [84 + 50 * 2 * 64 * 24]);
    assert.deepEqual(r.load.after, [0], 'the bytes sent to the worker were transferred');
  });

  test('slice: progress in stage order, fractions nondecreasing, result buffers transferred', async () => {
    const r = await page.evaluate(async () => {
      window.workerTransfers.length = 0;
      const events = [];
      let settledEarly = false;
      const result = await window.slicer.slice(window.torusId, { layer_height: 0.3, walls: 2, infill: 20 },
        { onProgress: (p) => events.push(p) });
      settledEarly = events.length === 0;
      window.torusLayers = result.layers;
      return {
        events, settledEarly, report: result.report, info: result.info,
        programStart: result.program.slice(0, 200), programLength: result.program.length,
        types: [result.preview.positions, result.preview.features, result.preview.layers,
          result.preview.machine, result.mesh.positions, result.mesh.indices].map((a) => a.constructor.name),
        machineFloats: result.preview.machine.length, programExtension: result.programExtension,
        segments: result.preview.features.length, previewFloats: result.preview.positions.length,
        layerIdsLength: result.preview.layers.length,
        maxLayer: result.preview.layers.reduce((m, v) => Math.max(m, v), 0),
        // Typed arrays of the preview (positions, features, layers, machine; with the curved-layer
        // builds also axes, poses, surfacePositions, surfaceTriangles, surfaceLayers, missedVoxels,
        // supportVoxels, curves) and their lengths.
        previewArrays: Object.fromEntries(Object.entries(result.preview).filter(([, a]) => ArrayBuffer.isView(a)).map(([k, a]) => [k, a.length])),
        spy: await (async () => {
          // The spy reports in a message right after the result: wait for it.
          for (let i = 0; i < 100 && !window.workerTransfers.some((x) => x.replyType === 'result'); ++i) {
            await new Promise((res) => setTimeout(res, 10));
          }
          return window.workerTransfers.slice();
        })(),
      };
    });
    assert.equal(r.settledEarly, false, 'progress came before the result');
    // Stages: each appears in one contiguous run (pipeline order), fractions nondecreasing.
    const order = [];
    const last = new Map();
    for (const { stage, fraction } of r.events) {
      assert.equal(typeof stage, 'string');
      assert.ok(fraction >= 0 && fraction <= 1, `fraction ${fraction} in [0,1]`);
      if (order[order.length - 1] !== stage) {
        assert.ok(!order.includes(stage), `stage ${stage} came back after ${order[order.length - 1]}: ${order}`);
        order.push(stage);
      }
      if (last.has(stage)) assert.ok(fraction >= last.get(stage), `${stage}: ${fraction} < ${last.get(stage)}`);
      last.set(stage, fraction);
    }
    assert.equal(order[0], 'read', `first stage is read (${order})`);
    assert.equal(order[order.length - 1], 'program', `last stage is program (${order})`);
    assert.equal(last.get('program'), 1);
    // Result content.
    assert.deepEqual(r.types, ['Float32Array', 'Uint8Array', 'Uint32Array', 'Float32Array', 'Float32Array', 'Uint32Array']);
    assert.equal(r.programExtension, 'gcode', 'the default machine writes G-code');
    assert.equal(r.machineFloats, 6 * r.segments, 'machine values per segment');
    assert.ok(r.programLength > 1000 && /G1 /.test(r.programStart + 'G1 '), 'G-code text');
    assert.equal(r.report.layers, Math.round(12 / 0.3), 'torus of height 12 mm at 0.3 mm');
    assert.equal(r.previewFloats, 6 * r.segments);
    assert.equal(r.layerIdsLength, r.segments);
    assert.equal(r.maxLayer, r.report.layers - 1);
    // The worker transferred (detached) every result buffer.
    const spy = r.spy.find((s) => s.replyType === 'result');
    assert.ok(spy, 'spy saw the slice result');
    const previewBuffers = Object.keys(r.previewArrays).length;
    // 28: the tool path's, each method's section and the simulated program's failing points.
    assert.ok(previewBuffers === 4 || previewBuffers === 28, `preview arrays: ${JSON.stringify(r.previewArrays)}`);
    assert.equal(spy.before.length, 1 + previewBuffers + 2, `program + ${previewBuffers} preview + 2 mesh buffers in the transfer list`);
    if (previewBuffers === 28) {
      // A planar slice: nozzle axes and platform poses per segment, no surfaces or voxel cells;
      // NL curve indices (iso-planar fill) either none or one per segment.
      assert.equal(r.previewArrays.axes, 3 * r.segments);
      assert.equal(r.previewArrays.poses, 7 * r.segments);
      for (const k of ['surfacePositions', 'surfaceTriangles', 'surfaceLayers', 'missedVoxels', 'supportVoxels', 'fieldPositions', 'fieldTriangles', 'fieldValues', 'nodePositions', 'nodeLayers', 'treeEdges', 'sequence', 'skippedSegments', 'skippedLayers', 'partPositions', 'partTriangles', 'partIds', 'riskyBefore', 'riskyAfter']) assert.equal(r.previewArrays[k], 0, k);
      assert.ok(r.previewArrays.curves === 0 || r.previewArrays.curves === r.segments, `curves: ${r.previewArrays.curves}`);
    }
    assert.ok(spy.before[0] === r.programLength, 'program bytes (ASCII G-code) transferred');
    assert.ok(spy.after.every((n) => n === 0), `detached after postMessage: ${spy.after}`);
  });

  // Issue 7 item 9: the worker posts every level of the multidir plane search (never throttled)
  // with its J_G, before the result.
  test('slice: every multidir search level comes as progress.search before the result', async () => {
    const r = await page.evaluate(async () => {
      const events = [];
      const result = await window.slicer.slice({ name: 'l.stl', bytes: window.meshes.lBracketStl() },
        { method: 'multidir', machine: 'table5', layer_height: 0.3 }, { onProgress: (p) => events.push(p) });
      return { events, settledEarly: events.length === 0, multidir: result.report.multidir };
    });
    assert.equal(r.settledEarly, false, 'progress came before the result');
    const { levels } = checkSearchLevels(r.events, r.multidir);
    assert.ok(levels.length >= 5, `${levels.length} search levels`);
    const decompose = r.events.filter((p) => p.stage === 'decompose').map((p) => p.fraction);
    decompose.forEach((f, i) => assert.ok(f >= 0 && f <= 1 && (i === 0 || f >= decompose[i - 1]), `decompose fraction ${f} at ${i}`));
    assert.equal(decompose[decompose.length - 1], 1);
  });

  test('cancel rejects with cancelled within 200 ms and the slicer works again', async (t) => {
    const r = await page.evaluate(async () => {
      const bytes = window.meshes.sphereStl(30, 400, 200);  // 159,600 triangles
      const { meshId } = await window.slicer.loadMesh('sphere.stl', bytes);
      const controller = new AbortController();
      let abortedAt = 0;
      let firstStage = null;
      const started = performance.now();
      const promise = window.slicer.slice(meshId, { layer_height: 0.05 }, {
        signal: controller.signal,
        onProgress: (p) => {
          if (!firstStage) {
            firstStage = p.stage;
            abortedAt = performance.now();
            controller.abort();
          }
        },
      });
      let code = null;
      try {
        await promise;
      } catch (e) {
        code = e.code;
      }
      const rejectMs = performance.now() - abortedAt;
      // A request pending on the worker at cancel time rejects too.
      const controller2 = new AbortController();
      const p2 = window.slicer.slice(window.torusId, { layer_height: 0.3 }, { signal: controller2.signal });
      const p3 = window.slicer.slice(window.torusId, { layer_height: 0.3 });
      await new Promise((res) => setTimeout(res, 5));
      controller2.abort();
      const codes = await Promise.allSettled([p2, p3]).then((s) => s.map((x) => x.reason && x.reason.code));
      // Works again: the torus bytes are re-sent to the new worker transparently.
      const again = await window.slicer.slice(window.torusId, { layer_height: 0.3, walls: 2, infill: 20 });
      const preAborted = await window.slicer.slice(window.torusId, {}, { signal: AbortSignal.abort() })
        .then(() => 'resolved', (e) => e.code);
      return { code, rejectMs, firstStage, totalMs: performance.now() - started, codes,
        againLayers: again.layers, expected: window.torusLayers, preAborted };
    });
    t.diagnostic(`cancel: rejected ${r.rejectMs.toFixed(1)} ms after abort (first stage ${r.firstStage})`);
    assert.equal(r.code, 'cancelled');
    assert.ok(r.rejectMs < 200, `rejected ${r.rejectMs.toFixed(1)} ms after abort`);
    assert.deepEqual(r.codes, ['cancelled', 'cancelled'], 'pending requests reject with cancelled');
    assert.equal(r.againLayers, r.expected, 'same result after respawn');
    assert.equal(r.preAborted, 'cancelled');
  });

  test('bad input rejects with its status code; a wasm crash respawns the worker', async () => {
    const r = await page.evaluate(async () => {
      const { OmnisliceError } = window.engine;
      const codeOf = (p) => p.then(() => 'resolved', (e) => (e instanceof OmnisliceError ? e.code : `not OmnisliceError: ${e}`));
      const garbage = new Uint8Array(300).fill(7).buffer;
      const out = {};
      out.empty = await codeOf(window.slicer.slice({ name: 'a.stl', bytes: new ArrayBuffer(0) }));
      out.garbage = await codeOf(window.slicer.loadMesh('junk.xyz', garbage));
      out.absurd = await codeOf(window.slicer.slice(window.torusId, { layer_height: -1 }));
      out.unknownKey = await codeOf(window.slicer.slice(window.torusId, { no_such_setting: 1 }));
      out.unknownMesh = await codeOf(window.slicer.slice('mesh-999'));
      out.afterErrors = (await window.slicer.slice(window.torusId, { layer_height: 0.3 })).layers;
      // Crash: the crashing request rejects internal, a queued one worker_failed; then it recovers.
      const crash = codeOf(window.slicer._debugCrash());
      const queued = codeOf(window.slicer.slice(window.torusId, { layer_height: 0.3 }));
      out.crash = await crash;
      out.queued = await queued;
      out.afterCrash = (await window.slicer.slice(window.torusId, { layer_height: 0.3 })).layers;
      out.verify = await window.slicer.verify('G28\n', window.torusId).then((v) => typeof v, (e) => e.code);
      return out;
    });
    assert.equal(r.empty, 'empty_input');
    assert.ok(['unsupported_format', 'parse_error'].includes(r.garbage), r.garbage);
    assert.equal(r.absurd, 'invalid_option');
    assert.equal(r.unknownKey, 'invalid_option');
    assert.equal(r.unknownMesh, 'invalid_option');
    assert.ok(r.afterErrors > 0);
    assert.equal(r.crash, 'internal');
    assert.equal(r.queued, 'worker_failed');
    assert.equal(r.afterCrash, r.afterErrors);
    assert.ok(['object', 'parse_error', 'invalid_option'].includes(r.verify), String(r.verify));
  });

  test('machines and parseMachine: built-in profiles; a profile comes back in the header form; a malformed one rejects with parse_error', async () => {
    const r = await page.evaluate(async () => {
      const { OmnisliceError } = window.engine;
      const good = await window.slicer.parseMachine(JSON.stringify({
        kind: 'rotary4', pivot: [0, 5, 12], axis_limits: { A: [-60, 60] }, nozzle: { diameter: 0.6 },
      }, null, 2));
      const fails = [];
      for (const text of ['{"kind": "rotary4", ', '[1, 2]', '{"pivot": [0, 0, 0]}',
        '{"kind": "rotary4", "axis_limits": {"A": [60, -60]}}']) {
        fails.push(await window.slicer.parseMachine(text).then(() => 'resolved',
          (e) => (e instanceof OmnisliceError ? `${e.code}: ${e.message}` : `not OmnisliceError: ${e}`)));
      }
      const machines = await window.slicer.machines({ bed_size: '200,180,150' });
      return { good, fails, machines };
    });
    assert.deepEqual(r.machines.map((x) => x.name), ['cartesian3', 'rotary4', 'table5', 'head4', 'head5', 'robot6-ur5', 'robot6-ur5-rated', 'robot6-irb1200', 'robot6-kr6']);
    assert.deepEqual(r.machines[0].profile.axis_limits.Y, [-90, 90], 'sized by bed_size');
    assert.equal(r.machines[3].profile.kind, 'head4');
    assert.equal(r.machines[3].profile.tilt_deg, 45);
    assert.equal(r.machines[4].profile.kind, 'head5');
    assert.deepEqual(r.machines[4].profile.tip_offset, [0, 0, -60]);
    assert.equal(r.machines[5].profile.kind, 'robot6');
    assert.equal(JSON.parse(r.machines[5].json).dh.length, 6);
    assert.equal(r.good.profile.kind, 'rotary4');
    assert.deepEqual(r.good.profile.pivot, [0, 5, 12]);
    assert.deepEqual(r.good.profile.axis_limits.A, [-60, 60]);
    assert.equal(r.good.profile.nozzle.diameter, 0.6);
    assert.ok(!/\n/.test(r.good.json) && JSON.parse(r.good.json).kind === 'rotary4', 'one-line JSON');
    for (const f of r.fails) assert.match(f, /^parse_error: machine JSON: \S/, f);
  });

  test('default URLs work; a bad wasm URL rejects with worker_failed; unloadMesh forgets', async () => {
    const r = await page.evaluate(async () => {
      const out = {};
      const plain = await window.engine.createSlicer();
      const { meshId, info } = await plain.loadMesh('box.stl', window.meshes.boxStl(10, 10, 4));
      out.faces = info.faces;
      out.layers = (await plain.slice(meshId, { layer_height: 0.2 })).layers;
      await plain.unloadMesh(meshId);
      out.afterUnload = await plain.slice(meshId).then(() => 'resolved', (e) => e.code);
      plain.dispose();
      out.afterDispose = await plain.slice({ name: 'b.stl', bytes: window.meshes.boxStl(1, 1, 1) })
        .then(() => 'resolved', (e) => e.code);
      out.badWasm = await window.engine.createSlicer({ wasmUrl: '/wasm/missing.mjs' })
        .then((s) => { s.dispose(); return 'resolved'; }, (e) => e.code);
      out.badWorker = await window.engine.createSlicer({ workerUrl: '/workers/missing.js' })
        .then((s) => { s.dispose(); return 'resolved'; }, (e) => e.code);
      return out;
    });
    assert.equal(r.faces, 12);
    assert.equal(r.layers, 20);
    assert.equal(r.afterUnload, 'invalid_option');
    assert.equal(r.afterDispose, 'cancelled');
    assert.equal(r.badWasm, 'worker_failed');
    assert.equal(r.badWorker, 'worker_failed');
  });

  test('stats: jobs count the answered requests, memory is the instance\'s, a replacement worker starts at zero', async () => {
    const r = await page.evaluate(async () => {
      const s = await window.engine.createSlicer({ workers: 1 });
      const out = { start: await s.stats() };
      const { meshId } = await s.loadMesh('box.stl', window.meshes.boxStl(10, 10, 4));
      await s.slice(meshId, { layer_height: 0.2 });
      await s.slice(meshId, { layer_height: 0.1 });
      out.after = await s.stats();
      // A cancel replaces the worker: a new instance, no jobs yet.
      const c = new AbortController();
      const p = s.slice({ name: 't.stl', bytes: window.meshes.torusStl(30, 10, 400, 125) }, {}, { signal: c.signal });
      setTimeout(() => c.abort(), 50);
      out.cancelled = await p.then(() => 'resolved', (e) => e.code);
      out.replaced = await s.stats();
      s.dispose();
      return out;
    });
    assert.equal(r.start.jobs, 0);
    assert.equal(r.start.workersStarted, 1);
    assert.ok(r.start.usedBytes > 0 && r.start.heapBytes >= r.start.usedBytes, JSON.stringify(r.start));
    assert.equal(r.after.jobs, 3, 'load and two slices');
    assert.ok(r.after.heapBytes >= r.start.heapBytes, 'linear memory never shrinks');
    assert.equal(r.cancelled, 'cancelled');
    assert.equal(r.replaced.workersStarted, 2);
    assert.equal(r.replaced.jobs, 0);
  });

  test('out_of_memory: the job rejects with it, the worker is replaced, the kept mesh slices again', async () => {
    const r = await page.evaluate(async () => {
      const s = await window.engine.createSlicer({ workers: 1 });
      const { meshId } = await s.loadMesh('cube.stl', window.meshes.boxStl(40, 40, 40));
      const out = { before: (await s.slice(meshId, { layer_height: 0.4 })).layers };
      out.refused = await s.slice(meshId, { method: 'voxel', machine: 'table5', memory_mb: 16 })
        .then(() => 'resolved', (e) => `${e.code}: ${e.message}`);
      out.stats = await s.stats();
      out.after = (await s.slice(meshId, { layer_height: 0.4 })).layers;
      s.dispose();
      return out;
    });
    assert.match(r.refused, /^out_of_memory: .*memory_mb = 16 MB/);
    assert.equal(r.stats.workersStarted, 2, 'a fresh worker after out_of_memory');
    assert.ok(r.before > 90, String(r.before));
    assert.equal(r.after, r.before, 'the same slice in the fresh worker (the mesh sent again)');
  });

  test('the main thread is not blocked while slicing', async (t) => {
    const r = await page.evaluate(async () => {
      const bytes = window.meshes.torusStl(30, 10, 400, 125);  // 100,000 triangles
      const { meshId } = await window.slicer.loadMesh('torus100k.stl', bytes);
      const longTasks = [];
      const observer = new PerformanceObserver((list) => {
        for (const e of list.getEntries()) longTasks.push({ start: e.startTime, ms: e.duration });
      });
      observer.observe({ type: 'longtask' });
      // Control: the observer sees a deliberate 80 ms block on the main thread.
      const busyStart = performance.now();
      while (performance.now() - busyStart < 80) { /* block */ }
      await new Promise((res) => setTimeout(res, 20));
      const control = longTasks.length;
      let ticks = 0;
      let maxGap = 0;
      let last = performance.now();
      let running = true;
      const tick = () => {
        const now = performance.now();
        maxGap = Math.max(maxGap, now - last);
        last = now;
        ++ticks;
        if (running) setTimeout(tick, 0);
      };
      setTimeout(tick, 0);
      const t0 = performance.now();
      const result = await window.slicer.slice(meshId, { layer_height: 0.2 });
      const sliceMs = performance.now() - t0;
      running = false;
      await new Promise((res) => setTimeout(res, 50));  // let the observer deliver
      observer.disconnect();
      const during = longTasks.filter((e) => e.start >= t0 - 1);
      return { control, during, ticks, maxGap, sliceMs, layers: result.layers };
    });
    t.diagnostic(`100k-triangle torus sliced in the worker in ${r.sliceMs.toFixed(0)} ms; `
      + `${r.ticks} timer ticks, longest gap ${r.maxGap.toFixed(0)} ms, long tasks ${r.during.length}`);
    assert.ok(r.control >= 1, 'the long-task observer works (control block seen)');
    assert.deepEqual(r.during, [], `main-thread tasks over 50 ms while slicing: ${JSON.stringify(r.during)}`);
    assert.ok(r.ticks >= r.sliceMs / 100, `timers kept running (${r.ticks} ticks in ${r.sliceMs.toFixed(0)} ms, longest gap ${r.maxGap.toFixed(0)} ms)`);
    assert.equal(r.layers, Math.round(20 / 0.2));
  });

  // Issue 28 item 2: method = auto's candidates in a pool of workers (workers/auto-pool.js): the
  // program is the one a single worker delivers; no main-thread task over 50 ms meanwhile; the
  // progress names each candidate; a crashed candidate is reported and the others still decide; a
  // cancel stops every worker and the pool works again.
  test('method = auto in a pool of 2 workers: the same program as one worker; survives a crash and a cancel', async (t) => {
    const r = await page.evaluate(async () => {
      const s = { method: 'auto', machine: 'table5', nozzle_diameter: 0.8, layer_height: 0.6, line_width: 0.9 };
      const bytes = window.meshes.lBracketStl(10);
      const one = await window.engine.createSlicer({ workers: 1 });
      const pool = await window.engine.createSlicer({ workers: 2 });
      const undated = (p) => p.slice(p.indexOf('\n'));
      try {
        const a = await one.slice({ name: 'l.stl', bytes }, s);
        const { meshId } = await pool.loadMesh('l.stl', bytes);
        const longTasks = [];
        const observer = new PerformanceObserver((list) => {
          for (const e of list.getEntries()) longTasks.push(e.duration);
        });
        observer.observe({ type: 'longtask' });
        const candidates = new Set();
        const t0 = performance.now();
        const b = await pool.slice(meshId, s, { onProgress: (p) => { if (p.candidate) candidates.add(p.candidate); } });
        const poolMs = performance.now() - t0;
        await new Promise((res) => setTimeout(res, 50));
        observer.disconnect();
        const crashed = await pool.slice(meshId, s, { _crashCandidate: b.report.auto.chosen });
        const controller = new AbortController();
        const cancelled = pool.slice(meshId, s, {
          signal: controller.signal,
          onProgress: (p) => { if (p.candidate === 'voxel') controller.abort(); },
        }).then(() => 'resolved', (e) => e.code);
        const cancelCode = await cancelled;
        const again = await pool.slice(meshId, s);
        return {
          same: undated(a.program) === undated(b.program), chosenOne: a.report.auto.chosen, chosenPool: b.report.auto.chosen,
          poolCandidates: b.report.auto.candidates.map((c) => `${c.method}:${c.status}:${c.stopped_early}`),
          auto: typeof b.report.timings_ms.auto, longTasks, progressOf: [...candidates].sort(), poolMs,
          crashed: crashed.report.auto.candidates.map((c) => `${c.method}:${c.status}`), crashedChosen: crashed.report.auto.chosen,
          crashedMethod: crashed.report.method, cancelCode, againSame: undated(again.program) === undated(b.program),
          workers: pool.workers,
        };
      } finally {
        one.dispose();
        pool.dispose();
      }
    });
    t.diagnostic(`auto in a pool of 2: ${r.poolMs.toFixed(0)} ms, chose ${r.chosenPool}`);
    assert.equal(r.workers, 2);
    assert.equal(r.chosenPool, r.chosenOne);
    assert.ok(r.same, 'the same program as one worker');
    assert.deepEqual(r.poolCandidates, ['planar:ok:false', 'multidir:ok:false', 'geodesic:ok:false', 'voxel:ok:false']);
    assert.equal(r.auto, 'number');
    assert.deepEqual(r.progressOf, ['geodesic', 'multidir', 'planar', 'voxel']);
    assert.deepEqual(r.longTasks, [], 'main-thread tasks over 50 ms while the pool ran');
    assert.ok(r.crashed.includes(`${r.chosenOne}:internal`), r.crashed.join(' '));
    assert.notEqual(r.crashedChosen, r.chosenOne);
    assert.equal(r.crashedMethod, r.crashedChosen);
    assert.equal(r.cancelCode, 'cancelled');
    assert.ok(r.againSame, 'after a cancel the pool delivers the same program');
  });
});
