// SPDX-License-Identifier: MIT
// The promise-based engine facade used by the page, the JS tests and vendors. It owns one slicer
// worker (slicer-worker.js), speaks protocol.js with it, and hides respawns: cancel terminates the
// worker and starts a new one; meshes are kept here and re-sent to a new worker transparently.
//
//   const slicer = await createSlicer();
//   const { meshId, info, mesh } = await slicer.loadMesh('part.stl', arrayBuffer, { up: 'y' });
//   const { program, report, preview } = await slicer.slice(meshId, { layer_height: 0.2 },
//     { onProgress: ({ stage, fraction, search }) => {}, signal: abortController.signal });
//   const verification = await slicer.verify(program, meshId);
//   slicer.dispose();
import { runAutoPool } from './auto-pool.js';
import { OmnisliceError, Reply, Request } from './protocol.js';

export { OmnisliceError };

const textDecoder = new TextDecoder();

function copyBytes(data, what) {
  if (data instanceof ArrayBuffer) return data.slice(0);
  if (ArrayBuffer.isView(data)) {
    return data.buffer.slice(data.byteOffset, data.byteOffset + data.byteLength);
  }
  throw new OmnisliceError('invalid_option', `${what} must be an ArrayBuffer or typed array`);
}

function cancelledError() {
  return new OmnisliceError('cancelled', 'cancelled');
}

class Slicer {
  #workerUrl;
  #wasmUrl;
  #worker = null;
  #ready = null;            // Promise resolved when the current worker answered init
  #pending = new Map();     // request id -> {resolve, reject, onProgress}
  #nextId = 1;
  #nextMesh = 1;
  #meshes = new Map();      // meshId -> {name, bytes: ArrayBuffer (private copy), placement}
  #loaded = new Map();      // meshId -> Promise of the load in the CURRENT worker
  #disposed = false;
  #poolSize = 1;
  #workersStarted = 0;     // this slicer's own worker: the first, and each one replacing it
  #helpers = [];            // further slicers for method = auto's candidates (started on first use)
  #helperMeshes = new Map();  // meshId -> [meshId in helper i (a Promise)]

  constructor({ workerUrl, wasmUrl, workers } = {}) {
    this.#workerUrl = workerUrl ? new URL(workerUrl, globalThis.location?.href)
      : new URL('./slicer-worker.js', import.meta.url);
    this.#wasmUrl = wasmUrl ? new URL(wasmUrl, globalThis.location?.href).href : undefined;
    this.#poolSize = workers === undefined ? defaultPoolSize() : Math.max(1, Math.floor(Number(workers) || 1));
  }

  /** Workers method = auto runs its candidates in (this slicer's own and helpers started on use). */
  get workers() {
    return this.#poolSize;
  }

  /** Start a worker and wait for `ready`. */
  start() {
    const worker = new Worker(this.#workerUrl, { type: 'module' });
    ++this.#workersStarted;
    this.#worker = worker;
    this.#loaded = new Map();
    worker.onmessage = (event) => this.#onMessage(worker, event.data);
    let wasReady = false;
    worker.onerror = (event) => {
      if (event && event.preventDefault) event.preventDefault();
      if (worker !== this.#worker) return;
      const message = `slicer worker failed: ${event && event.message || 'script error'}`;
      // A worker that never became ready is not respawned (that would loop on a broken URL).
      this.#restart(new OmnisliceError('worker_failed', message), wasReady);
    };
    const ready = this.#send(Request.INIT, { wasmUrl: this.#wasmUrl }, [], {}, false);
    ready.then(() => { wasReady = true; }, () => {});
    this.#ready = ready;
    return ready;
  }

  // Wait until the current worker is ready (follows respawns that happen meanwhile).
  async #whenReady() {
    for (;;) {
      const ready = this.#ready;
      await ready;
      if (ready === this.#ready) return;
    }
  }

  #onMessage(worker, msg) {
    if (worker !== this.#worker || !msg || typeof msg !== 'object') return;
    const entry = this.#pending.get(msg.id);
    if (!entry) return;  // e.g. a reply of a request already settled, or a test spy message
    switch (msg.type) {
      case Reply.PROGRESS:
        if (entry.onProgress) {
          const p = { stage: msg.stage, fraction: msg.fraction };
          if (msg.search) p.search = msg.search;
          try { entry.onProgress(p); } catch { /* caller bug */ }
        }
        break;
      case Reply.READY:
        this.#pending.delete(msg.id);
        entry.resolve({ version: msg.version });
        break;
      case Reply.RESULT:
        this.#pending.delete(msg.id);
        entry.resolve(msg.result);
        break;
      case Reply.ERROR: {
        this.#pending.delete(msg.id);
        const err = new OmnisliceError(msg.code, msg.message);
        // unsound_program: what the refused slice measured and where it fails.
        for (const key of ['report', 'info', 'preview', 'mesh']) {
          if (msg[key] !== undefined) err[key] = msg[key];
        }
        entry.reject(err);
        if (msg.fatal) {
          // The wasm instance crashed: discard the worker; other requests fail with worker_failed.
          this.#restart(new OmnisliceError('worker_failed', `slicer worker crashed: ${msg.message}`), true);
        } else if (msg.code === 'out_of_memory') {
          // The instance is sound, but the heap it grew never shrinks: a fresh worker, so the
          // next job (a smaller model, a coarser setting) starts from a small heap.
          this.#restart(new OmnisliceError('worker_failed', `slicer worker replaced (out of memory): ${msg.message}`), true);
        }
        break;
      }
      default:
        break;
    }
  }

  // Post a request to the current worker; resolves with the reply's result.
  #send(type, payload, transfer = [], { onProgress } = {}, waitReady = true) {
    const run = () => new Promise((resolve, reject) => {
      if (this.#disposed) { reject(new OmnisliceError('cancelled', 'slicer disposed')); return; }
      if (!this.#worker) { reject(new OmnisliceError('worker_failed', 'no slicer worker')); return; }
      const id = this.#nextId++;
      this.#pending.set(id, { resolve, reject, onProgress });
      try {
        this.#worker.postMessage({ id, type, payload }, transfer);
      } catch (e) {
        this.#pending.delete(id);
        reject(new OmnisliceError('worker_failed', `cannot post ${type}: ${e.message || e}`));
      }
    });
    return waitReady ? this.#whenReady().then(run) : run();
  }

  // Terminate the worker, reject everything pending with `error`, start a fresh worker.
  #restart(error, respawn = true) {
    const worker = this.#worker;
    this.#worker = null;
    if (worker) worker.terminate();
    const pending = [...this.#pending.values()];
    this.#pending.clear();
    for (const p of pending) p.reject(error);
    if (this.#disposed) return;
    if (respawn) {
      this.start().catch(() => {});
    } else {
      this.#ready = Promise.reject(error);
      this.#ready.catch(() => {});
    }
  }

  // Make sure meshId is stored in the current worker (re-sends the kept bytes after a respawn).
  #ensureLoaded(meshId) {
    const mesh = this.#meshes.get(meshId);
    if (!mesh) return Promise.reject(new OmnisliceError('invalid_option', `unknown meshId ${meshId}`));
    let p = this.#loaded.get(meshId);
    if (!p) {
      const bytes = mesh.bytes.slice(0);
      const loaded = this.#loaded;
      p = this.#send(Request.LOAD, { meshId, name: mesh.name, bytes, placement: mesh.placement }, [bytes]);
      loaded.set(meshId, p);
      p.catch(() => { if (loaded.get(meshId) === p) loaded.delete(meshId); });
    }
    return p;
  }

  // {meshId} or {file} payload part for a meshId or a {name, bytes} file; with its transfer list.
  async #target(meshIdOrFile) {
    if (typeof meshIdOrFile === 'string') {
      await this.#ensureLoaded(meshIdOrFile);
      return { part: { meshId: meshIdOrFile }, transfer: [] };
    }
    if (meshIdOrFile && typeof meshIdOrFile === 'object' && 'bytes' in meshIdOrFile) {
      const bytes = copyBytes(meshIdOrFile.bytes, 'file.bytes');
      return { part: { file: { name: String(meshIdOrFile.name ?? ''), bytes } }, transfer: [bytes] };
    }
    throw new OmnisliceError('invalid_option', 'expected a meshId from loadMesh or a file {name, bytes}');
  }

  // Run fn (which issues requests) under an AbortSignal: abort terminates and respawns the worker.
  async #cancellable(signal, fn) {
    if (signal && signal.aborted) throw cancelledError();
    if (!signal) return fn();
    let onAbort;
    const aborted = new Promise((_, reject) => {
      onAbort = () => {
        reject(cancelledError());
        this.#restart(cancelledError(), true);
      };
      signal.addEventListener('abort', onAbort, { once: true });
    });
    try {
      return await Promise.race([fn(), aborted]);
    } finally {
      signal.removeEventListener('abort', onAbort);
    }
  }

  async loadMesh(name, arrayBuffer, placement = {}) {
    const bytes = copyBytes(arrayBuffer, 'arrayBuffer');
    const meshId = `mesh-${this.#nextMesh++}`;
    this.#meshes.set(meshId, { name: String(name ?? ''), bytes, placement: { ...placement } });
    try {
      const result = await this.#ensureLoaded(meshId);
      return { meshId, info: result.info, mesh: result.mesh };
    } catch (e) {
      this.#meshes.delete(meshId);
      throw e;
    }
  }

  async slice(meshIdOrFile, settings = {}, options = {}) {
    if (settings && settings.method === 'auto' && this.#poolSize > 1) return this.#sliceAuto(meshIdOrFile, settings, options);
    return this.#sliceOne(meshIdOrFile, settings, options);
  }

  async #sliceOne(meshIdOrFile, settings = {}, { onProgress, signal } = {}) {
    return this.#cancellable(signal, async () => {
      const { part, transfer } = await this.#target(meshIdOrFile);
      if (signal && signal.aborted) throw cancelledError();
      const r = await this.#send(Request.SLICE, { ...part, settings }, transfer, { onProgress });
      // The G-code arrives as transferred bytes; decoding a large program to a string costs the
      // main thread tens of milliseconds, so it happens only when `program` is first read.
      const programBytes = new Uint8Array(r.program);
      let text = null;
      return {
        programBytes,
        get program() {
          if (text === null) text = textDecoder.decode(programBytes);
          return text;
        },
        programExtension: r.programExtension || 'gcode',
        report: r.report, info: r.info, layers: r.layers, preview: r.preview, mesh: r.mesh,
      };
    });
  }

  // The helper slicer of lane i (1 ..): started on first use, kept until dispose.
  async #helper(i) {
    if (!this.#helpers[i - 1]) {
      const h = new Slicer({ workerUrl: this.#workerUrl, wasmUrl: this.#wasmUrl, workers: 1 });
      const started = h.start().then(() => h);
      started.catch(() => { if (this.#helpers[i - 1] === started) this.#helpers[i - 1] = undefined; h.dispose(); });
      this.#helpers[i - 1] = started;
    }
    return this.#helpers[i - 1];
  }

  // meshId's id in the helper of lane i (loaded there once).
  async #helperMesh(i, meshId) {
    let ids = this.#helperMeshes.get(meshId);
    if (!ids) this.#helperMeshes.set(meshId, ids = []);
    if (!ids[i]) {
      const mesh = this.#meshes.get(meshId);
      if (!mesh) throw new OmnisliceError('invalid_option', `unknown meshId ${meshId}`);
      const h = await this.#helper(i);
      const p = h.loadMesh(mesh.name, mesh.bytes, mesh.placement).then((r) => r.meshId);
      p.catch(() => { if (ids[i] === p) ids[i] = undefined; });
      ids[i] = p;
    }
    return ids[i];
  }

  // method = auto with its candidates in a pool of workers (auto-pool.js): this slicer's worker
  // plans and chooses (the core's rule) and runs candidates, as do the helpers.
  async #sliceAuto(meshIdOrFile, settings, { onProgress, signal, _crashCandidate } = {}) {
    if (signal && signal.aborted) throw cancelledError();
    let meshId = meshIdOrFile;
    let temporary = false;
    if (typeof meshIdOrFile !== 'string') {
      if (!meshIdOrFile || typeof meshIdOrFile !== 'object' || !('bytes' in meshIdOrFile)) {
        throw new OmnisliceError('invalid_option', 'expected a meshId from loadMesh or a file {name, bytes}');
      }
      meshId = (await this.loadMesh(meshIdOrFile.name, meshIdOrFile.bytes)).meshId;
      temporary = true;
    }
    try {
      const { plan } = await this.#cancellable(signal, async () => {
        await this.#ensureLoaded(meshId);
        return this.#send(Request.AUTO_PLAN, { meshId, settings });
      });
      const run = async (lane, k, candidateSettings, progress) => {
        const slicer = lane === 0 ? this : await this.#helper(lane);
        if (_crashCandidate && plan.candidates[k].method === _crashCandidate) {
          await slicer._debugCrash();  // test hook: this candidate's worker crashes
        }
        const id = lane === 0 ? meshId : await this.#helperMesh(lane, meshId);
        return lane === 0 ? this.#sliceOne(id, candidateSettings, { onProgress: progress, signal })
          : slicer.slice(id, candidateSettings, { onProgress: progress, signal });
      };
      const choose = async (candidates) => {
        const r = await this.#cancellable(signal, () => this.#send(Request.AUTO_CHOOSE, { settings, candidates }));
        return r.decision;
      };
      const { decision, result, results, ms } = await runAutoPool({
        plan, settings, size: this.#poolSize, run, choose, onProgress, signal,
      });
      if (decision.chosen < 0) throw new OmnisliceError(decision.status, decision.message);
      result.report.auto = decision.auto;
      // Every candidate's result by method (the page shows a sound one at once when chosen).
      result.candidates = {};
      results.forEach((r, k) => { if (r) result.candidates[plan.candidates[k].method] = r; });
      if (result.report.timings_ms) result.report.timings_ms.auto = ms;
      if (decision.status !== 'ok') {
        // verify = refuse and the best is unsound: no program; the report and preview say why.
        const err = new OmnisliceError(decision.status, decision.message);
        for (const key of ['report', 'info', 'preview', 'mesh']) err[key] = result[key];
        throw err;
      }
      return result;
    } finally {
      if (temporary) this.unloadMesh(meshId).catch(() => {});
    }
  }

  async info(meshIdOrFile, placement = {}, { signal } = {}) {
    return this.#cancellable(signal, async () => {
      const { part, transfer } = await this.#target(meshIdOrFile);
      return this.#send(Request.INFO, { ...part, placement }, transfer);
    });
  }

  async verify(program, meshIdOrFile, { onProgress, signal, memoryMb } = {}) {
    if (typeof program !== 'string') throw new OmnisliceError('invalid_option', 'program must be a string');
    return this.#cancellable(signal, async () => {
      const { part, transfer } = await this.#target(meshIdOrFile);
      const payload = { ...part, program, ...(memoryMb !== undefined ? { memoryMb } : {}) };
      const r = await this.#send(Request.VERIFY, payload, transfer, { onProgress });
      return r.report;
    });
  }

  /**
   * Replay a program (G-code, robot CSV or URScript) through its declared machine. Resolves with
   * {profile, format, layers, preview: {positions, features, layers, machine}} for the machine
   * animation; rejects with the reader's code (parse_error with the line, unsupported_format).
   */
  async replay(program, { signal } = {}) {
    if (typeof program !== 'string') throw new OmnisliceError('invalid_option', 'program must be a string');
    return this.#cancellable(signal, () => this.#send(Request.REPLAY, { program }));
  }

  /**
   * The core's settings table in listing order: [{key, type, default, min, max, unit, help,
   * choices, method}] (wasm/omnislice.js settingsSchema): defaults and ranges come from here.
   */
  async settingsSchema() {
    const r = await this.#send(Request.SETTINGS, {});
    return r.schema;
  }

  /**
   * The built-in machine profiles in display order: [{name, profile, json}], sized by the
   * settings' bed_size and nozzle (defaults when not given).
   */
  async machines(settings = {}) {
    const r = await this.#send(Request.MACHINES, { settings });
    return r.machines;
  }

  /**
   * Check a machine profile JSON (a user's profile file) with the core's parser. Resolves with
   * {profile: object, json: string}; json is one line, for the `machine_json` setting. Rejects
   * with OmnisliceError 'parse_error' (the core's message) when the profile is malformed.
   */
  async parseMachine(text) {
    if (typeof text !== 'string') throw new OmnisliceError('invalid_option', 'machine JSON must be a string');
    return this.#send(Request.PARSE_MACHINE, { json: text });
  }

  /** Forget a mesh (here and in the worker). */
  async unloadMesh(meshId) {
    this.#meshes.delete(meshId);
    const ids = this.#helperMeshes.get(meshId) || [];
    this.#helperMeshes.delete(meshId);
    ids.forEach((p, i) => {
      if (p) Promise.all([p, this.#helpers[i - 1]]).then(([id, h]) => h && h.unloadMesh(id)).catch(() => {});
    });
    if (this.#loaded.delete(meshId)) await this.#send(Request.UNLOAD, { meshId });
  }

  /**
   * The slicer's own worker's memory and work: {heapBytes (its wasm linear memory, which only
   * grows), usedBytes (what the core's allocator holds: a leak raises it), blocks, jobs (requests
   * that worker answered), workersStarted (1 + every replacement after a crash or a cancel)}.
   * Helpers of method = auto's pool are not counted.
   */
  async stats() {
    const r = await this.#send(Request.STATS, {});
    return { ...r, workersStarted: this.#workersStarted };
  }

  /** Test hook: crash the wasm instance in the worker (rejects with code 'internal'). */
  _debugCrash() {
    return this.#send(Request.DEBUG_CRASH, {});
  }

  dispose() {
    if (this.#disposed) return;
    this.#disposed = true;
    const worker = this.#worker;
    this.#worker = null;
    if (worker) worker.terminate();
    const pending = [...this.#pending.values()];
    this.#pending.clear();
    for (const p of pending) p.reject(new OmnisliceError('cancelled', 'slicer disposed'));
    this.#meshes.clear();
    this.#loaded = new Map();
    for (const h of this.#helpers) if (h) h.then((x) => x.dispose(), () => {});
    this.#helpers = [];
    this.#helperMeshes.clear();
  }
}

// Memory one worker may need for a candidate (a wasm heap of a voxel or geodesic slice of a
// model of a few hundred thousand triangles; measured in scripts/bench.mjs's auto rows).
const WORKER_MEMORY_GIB = 1;

/**
 * Workers for method = auto's candidates: the cores (navigator.hardwareConcurrency) less one for
 * the page, at most what the device's memory (navigator.deviceMemory, where the browser tells it)
 * holds at WORKER_MEMORY_GIB each, at most 4 (there are at most 5 candidates, the first is short).
 */
export function defaultPoolSize() {
  const nav = globalThis.navigator || {};
  const cores = Number(nav.hardwareConcurrency) || 1;
  let size = Math.min(4, Math.max(1, cores - (cores > 2 ? 1 : 0)));
  if (Number(nav.deviceMemory) > 0) size = Math.min(size, Math.max(1, Math.floor(nav.deviceMemory / WORKER_MEMORY_GIB) - 1));
  return size;
}

/**
 * Create a slicer backed by a module worker. Resolves after the worker answered `ready`.
 * @param {{workerUrl?: string|URL, wasmUrl?: string|URL, workers?: number}} [options]
 *   workerUrl: slicer-worker.js (default: next to this file); wasmUrl: omnislice.mjs (default:
 *   /wasm/omnislice.mjs relative to the worker); workers: how many workers method = auto runs
 *   its candidates in (default defaultPoolSize(); 1: one after another in this slicer's worker,
 *   as the core does in wasm). The delivered program is the same either way.
 */
export async function createSlicer(options = {}) {
  const slicer = new Slicer(options);
  try {
    await slicer.start();
  } catch (e) {
    slicer.dispose();
    throw e instanceof OmnisliceError ? e : new OmnisliceError('worker_failed', String(e && e.message || e));
  }
  return slicer;
}
