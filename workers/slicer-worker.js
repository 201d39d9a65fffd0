// SPDX-License-Identifier: MIT
// ES-module web worker running the wasm slicer (new Worker(url, {type: 'module'})). Speaks the
// protocol of protocol.js; all wasm work happens here so the page's main thread never blocks.
import { loadOmnislice } from '../wasm/omnislice.js';
import {
  OmnisliceError, PROTOCOL_VERSION, Reply, Request, errorReply, transferList,
} from './protocol.js';

let enginePromise = null;  // Promise<Omnislice> once `init` arrived
const meshes = new Map();  // meshId -> {name, bytes: Uint8Array, placement}
let jobs = 0;              // requests answered (init and stats not counted)

function post(message, transfer = []) {
  self.postMessage(message, transfer);
}

// Progress replies, throttled: every stage change, every +1 % and the end of a stage. A report
// with a search level (progress.search) is always posted, at no less than the stage's last
// fraction: the page draws every level (a few dozen per decomposition).
function progressPoster(id) {
  let lastStage = null;
  let lastFraction = -1;
  return ({ stage, fraction, search }) => {
    const f = Math.min(1, Math.max(0, Number(fraction) || 0));
    if (stage !== lastStage) {
      lastStage = stage;
      lastFraction = -1;
    }
    if (search) {
      lastFraction = Math.max(lastFraction, f);
      const { line, level, J_G, beams } = search;
      post({ id, type: Reply.PROGRESS, stage, fraction: lastFraction, search: { line, level, J_G, beams } });
      return;
    }
    if (f < lastFraction) return;  // never let a stage go backwards
    if (lastFraction < 0 || f >= 1 || f - lastFraction >= 0.01) {
      if (f === lastFraction) return;
      lastFraction = f;
      post({ id, type: Reply.PROGRESS, stage, fraction: f });
    }
  };
}

async function engine() {
  if (!enginePromise) throw new OmnisliceError('worker_failed', 'worker not initialised (send init first)');
  return enginePromise;
}

// The mesh a request refers to: {name, bytes, placement}.
function meshOf(payload) {
  if (payload.meshId !== undefined && payload.meshId !== null) {
    const m = meshes.get(payload.meshId);
    if (!m) throw new OmnisliceError('invalid_option', `unknown meshId ${payload.meshId}`);
    return m;
  }
  const file = payload.file;
  if (!file || !(file.bytes instanceof ArrayBuffer || ArrayBuffer.isView(file.bytes))) {
    throw new OmnisliceError('invalid_option', 'request needs a meshId or file {name, bytes}');
  }
  const bytes = file.bytes instanceof ArrayBuffer ? new Uint8Array(file.bytes)
    : new Uint8Array(file.bytes.buffer, file.bytes.byteOffset, file.bytes.byteLength);
  return { name: String(file.name ?? ''), bytes, placement: {} };
}

const handlers = {
  async [Request.INIT](id, payload) {
    if (!enginePromise) {
      const wasmUrl = payload && payload.wasmUrl
        ? new URL(payload.wasmUrl, self.location.href)
        : new URL('../wasm/omnislice.mjs', import.meta.url);
      enginePromise = loadOmnislice({ moduleUrl: wasmUrl.href });
      enginePromise.catch(() => { enginePromise = null; });
    }
    try {
      await enginePromise;
    } catch (e) {
      throw new OmnisliceError('worker_failed', `cannot load the wasm module: ${e.message || e}`);
    }
    post({ id, type: Reply.READY, version: PROTOCOL_VERSION });
  },

  async [Request.LOAD](id, payload) {
    const e = await engine();
    const { meshId, name, bytes, placement = {} } = payload;
    if (meshId === undefined || meshId === null) throw new OmnisliceError('invalid_option', 'load needs a meshId');
    const mesh = meshOf({ file: { name, bytes } });
    mesh.placement = placement;
    const { info, mesh: placed } = e.info(mesh.bytes, mesh.name, placement,
      { onProgress: progressPoster(id) });
    meshes.set(meshId, mesh);
    post({ id, type: Reply.RESULT, result: { meshId, info, mesh: placed } },
      transferList(placed.positions, placed.indices));
  },

  async [Request.UNLOAD](id, payload) {
    meshes.delete(payload.meshId);
    post({ id, type: Reply.RESULT, result: { meshId: payload.meshId } });
  },

  async [Request.INFO](id, payload) {
    const e = await engine();
    const m = meshOf(payload);
    const placement = { ...m.placement, ...(payload.placement || {}) };
    const { info, mesh } = e.info(m.bytes, m.name, placement, { onProgress: progressPoster(id) });
    post({ id, type: Reply.RESULT, result: { info, mesh } },
      transferList(mesh.positions, mesh.indices));
  },

  async [Request.SLICE](id, payload) {
    const e = await engine();
    const m = meshOf(payload);
    const settings = { ...m.placement, ...(payload.settings || {}) };
    const r = e.slice(m.bytes, m.name, settings,
      { onProgress: progressPoster(id), programAs: 'bytes' });
    const result = {
      program: r.program.buffer, programExtension: r.programExtension, report: r.report,
      info: r.info, layers: r.layers, preview: r.preview, mesh: r.mesh,
    };
    post({ id, type: Reply.RESULT, result },
      transferList(r.program, ...Object.values(r.preview), r.mesh.positions, r.mesh.indices));
  },

  async [Request.AUTO_PLAN](id, payload) {
    const e = await engine();
    const m = meshOf(payload);
    const plan = e.autoPlan(m.bytes, m.name, { ...m.placement, ...(payload.settings || {}) });
    post({ id, type: Reply.RESULT, result: { plan } });
  },

  async [Request.AUTO_CHOOSE](id, payload) {
    const e = await engine();
    const decision = e.autoChoose(payload.settings || {}, payload.candidates || []);
    post({ id, type: Reply.RESULT, result: { decision } });
  },

  async [Request.VERIFY](id, payload) {
    const e = await engine();
    const m = meshOf(payload);
    const report = e.verify(String(payload.program ?? ''), m.bytes, m.name,
      { onProgress: progressPoster(id), ...(payload.memoryMb !== undefined ? { memoryMb: payload.memoryMb } : {}) });
    post({ id, type: Reply.RESULT, result: { report } });
  },

  async [Request.REPLAY](id, payload) {
    const e = await engine();
    const r = e.replay(String(payload.program ?? ''));
    post({ id, type: Reply.RESULT, result: r },
      transferList(r.preview.positions, r.preview.features, r.preview.layers, r.preview.machine, r.preview.poses));
  },

  async [Request.MACHINES](id, payload) {
    const e = await engine();
    post({ id, type: Reply.RESULT, result: { machines: e.machines(payload.settings || {}) } });
  },

  async [Request.SETTINGS](id) {
    const e = await engine();
    post({ id, type: Reply.RESULT, result: { schema: e.settingsSchema() } });
  },

  async [Request.PARSE_MACHINE](id, payload) {
    const e = await engine();
    const { profile, json } = e.parseMachine(String(payload.json ?? ''));
    post({ id, type: Reply.RESULT, result: { profile, json } });
  },

  async [Request.STATS](id) {
    const e = await engine();
    post({ id, type: Reply.RESULT, result: { ...e.heapStats(), jobs } });
  },

  async [Request.DEBUG_CRASH]() {
    const e = await engine();
    e.raw._abortForTest();  // throws a RuntimeError (wasm abort); reported as fatal below
  },
};

self.onmessage = async (event) => {
  const { id, type, payload } = event.data || {};
  const handler = handlers[type];
  try {
    if (!handler) throw new OmnisliceError('invalid_option', `unknown request type ${type}`);
    if (type !== Request.INIT && type !== Request.STATS) ++jobs;
    await handler(id, payload || {});
  } catch (error) {
    let err = error;
    if (!(error instanceof OmnisliceError)) {
      // Anything not raised by the wrapper is a crash of this worker: it must be replaced.
      err = new OmnisliceError('internal', `worker crashed: ${error && error.message || error}`);
      err.fatal = true;
    }
    const reply = errorReply(id, err);
    post(reply, transferList(...Object.values(reply.preview || {}), ...Object.values(reply.mesh || {})));
  }
};
