// SPDX-License-Identifier: MIT
// omnislice/node: the embedding API (web/omnislice-embed.js: createSlicer, sliceFile, ...) in
// Node 18+, for portals' servers and batch jobs. The same wasm core and worker protocol run in
// worker_threads instead of browser workers:
//
//   import { sliceFile } from 'omnislice/node';
//   const result = await sliceFile('part.stl', { layer_height: 0.2, machine: 'table5' });
//   fs.writeFileSync(result.fileName, result.programBytes);
//
// sliceFile also takes {name, bytes} and Blobs, as in the browser. createSlicer() answers the
// facade's whole API (loadMesh, slice, verify, machines, settingsSchema, dispose, ...). Call
// dispose() on a slicer you made, or disposeSharedSlicer() after sliceFile, so the process can
// exit (a worker thread keeps it alive).
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { Worker as ThreadWorker } from 'node:worker_threads';

/** The browser Worker interface the facade uses (onmessage, onerror, postMessage, terminate). */
class NodeWorker {
  #thread;
  onmessage = null;
  onerror = null;

  constructor(url) {
    this.#thread = new ThreadWorker(new URL('./worker-thread.mjs', import.meta.url), {
      workerData: { url: String(url) },
    });
    this.#thread.on('message', (data) => { if (this.onmessage) this.onmessage({ data }); });
    this.#thread.on('error', (err) => {
      if (this.onerror) this.onerror({ message: err && err.message || String(err), preventDefault() {} });
    });
  }

  postMessage(message, transfer = []) {
    this.#thread.postMessage(message, transfer);
  }

  terminate() {
    this.#thread.terminate();
  }
}

// The facade starts workers with the global Worker; Node has none (a global one, e.g. a
// polyfill, is left alone). navigator.hardwareConcurrency (Node 21+) sizes method = auto's pool;
// older Node: the cores os reports.
if (typeof globalThis.Worker === 'undefined') globalThis.Worker = NodeWorker;
if (typeof globalThis.navigator === 'undefined') {
  Object.defineProperty(globalThis, 'navigator', { value: { hardwareConcurrency: os.cpus().length }, configurable: true });
}

const embed = await import('../web/omnislice-embed.js');
export const {
  createSlicer, OmnisliceError, PLACEMENT_KEYS, programFileName, sharedSlicer, disposeSharedSlicer,
  programBlob,
} = embed;

/**
 * Slice one file: a path, or what the browser's sliceFile takes ({name, bytes}, a Blob).
 * @returns {Promise<object>} the slice result plus fileName (see docs/EMBEDDING.md)
 */
export async function sliceFile(file, settings = {}, options = {}) {
  if (typeof file === 'string' || file instanceof URL) {
    const filePath = file instanceof URL ? file : path.resolve(file);
    let bytes;
    try {
      bytes = fs.readFileSync(filePath);
    } catch (err) {
      throw new embed.OmnisliceError('io_error', `cannot read ${file}: ${err.message}`);
    }
    const name = options.name || path.basename(String(file instanceof URL ? file.pathname : file));
    return embed.sliceFile({ name, bytes: new Uint8Array(bytes.buffer, bytes.byteOffset, bytes.byteLength) }, settings,
      { ...options, name });
  }
  return embed.sliceFile(file, settings, options);
}
