// SPDX-License-Identifier: MIT
// A worker thread of scripts/bench.mjs's wasm pool (method = auto's candidates side by side, as
// the page's workers run them): its own wasm instance; {id, bytes, name, settings} -> {id, report,
// heapBytes} or {id, error: {code, message}}.
import fs from 'node:fs';
import path from 'node:path';
import { pathToFileURL } from 'node:url';
import { parentPort, workerData } from 'node:worker_threads';

const { wasmDir } = workerData;
const wrapper = await import(pathToFileURL(path.join(wasmDir, 'omnislice.js')).href);
const m = await wrapper.loadOmnislice({
  moduleUrl: pathToFileURL(path.join(wasmDir, 'omnislice.mjs')).href,
  wasmBinary: fs.readFileSync(path.join(wasmDir, 'omnislice.wasm')),
});
const { torusStl } = await import('../tests/js/fixtures/meshes.js');
m.slice(torusStl(20, 6, 200, 60), 'warmup.stl', { layer_height: 0.3 });  // as bench.mjs's warm-up

parentPort.on('message', ({ id, bytes, name, settings }) => {
  try {
    const r = m.slice(bytes, name, settings, { programAs: 'bytes' });
    const heap = m.raw.HEAPU8 || (m.raw.wasmMemory && new Uint8Array(m.raw.wasmMemory.buffer));
    parentPort.postMessage({ id, report: r.report, heapBytes: heap ? heap.buffer.byteLength : null });
  } catch (e) {
    parentPort.postMessage({ id, error: { code: e.code || 'internal', message: String(e.message || e) } });
  }
});
parentPort.postMessage({ ready: true });
