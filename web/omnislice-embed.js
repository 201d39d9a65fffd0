// SPDX-License-Identifier: MIT
// Embedding API for vendor pages: the engine facade (createSlicer, OmnisliceError) plus small
// conveniences. Import it from the server that hosts Omnislice (same origin as the page: browsers
// only start module workers from the page's own origin):
//
//   import { sliceFile } from '/omnislice-embed.js';
//   const result = await sliceFile(fileInput.files[0], { layer_height: 0.2, fit_mm: 80 },
//     { onProgress: ({ stage, fraction }) => {}, signal });
//   link.href = URL.createObjectURL(programBlob(result)); link.download = result.fileName;
//
// The import below is relative so the module works wherever the folders keep their layout
// (<root>/omnislice-embed.js next to <root>/workers/ and <root>/wasm/).
import { createSlicer, OmnisliceError } from '../workers/engine.js';
import { PLACEMENT_KEYS, placementOf } from './placement.js';
import { PROGRAM_KINDS, programExtension, programFileName } from './program-file.js';

export { createSlicer, OmnisliceError, PLACEMENT_KEYS, programFileName };

let shared = null;

/**
 * One slicer shared by the calls of this module that are not given their own (created on first
 * use; a failed start is not cached, so a later call tries again).
 * @returns {Promise<object>} the facade's slicer
 */
export function sharedSlicer() {
  if (!shared) {
    shared = createSlicer();
    shared.catch(() => { shared = null; });
  }
  return shared;
}

/** Dispose the shared slicer (its worker ends); the next call starts a new one. */
export async function disposeSharedSlicer() {
  const s = shared;
  shared = null;
  if (s) (await s.catch(() => null))?.dispose();
}

/** The program of a slice result as a Blob (make it when the user asks for it, not before). */
export function programBlob(result) {
  if (!result || !(result.programBytes instanceof Uint8Array)) {
    throw new OmnisliceError('invalid_option', 'programBlob needs a slice result with a program');
  }
  return new Blob([result.programBytes], { type: PROGRAM_KINDS[programExtension(result.programExtension)].mime });
}

/**
 * Slice one file in a single call: read it, load it, slice it, forget it.
 * @param {File|Blob|{name: string, bytes: ArrayBuffer|ArrayBufferView}} file  the mesh (.stl .obj
 *   .off .ply .3mf; the format is recognised from the name and the content)
 * @param {object} settings  slicing settings by key (layer_height, infill, direction, ...); the
 *   placement keys (fit_mm, up, rotate_*_deg, scale, center) place the mesh first
 * @param {{onProgress?: Function, signal?: AbortSignal, slicer?: object, name?: string}} options
 *   onProgress({stage, fraction, search?}) (search: a multidir search level, docs/EMBEDDING.md);
 *   signal aborts (rejects with code 'cancelled'); slicer: use this facade instead of the shared
 *   one; name: file name when `file` is a Blob without one
 * @returns {Promise<object>} the facade's slice result plus fileName (the program's file name:
 *   .gcode, or .csv / .script for a robot)
 * @throws {OmnisliceError} code and human message (e.g. 'truncated_file', 'open_mesh', 'cancelled')
 */
export async function sliceFile(file, settings = {}, { onProgress, signal, slicer, name } = {}) {
  if (!file) throw new OmnisliceError('invalid_option', 'sliceFile needs a file');
  const fileName = name || file.name || 'model.stl';
  let bytes;
  if (typeof file.arrayBuffer === 'function') bytes = await file.arrayBuffer();
  else if (file.bytes instanceof ArrayBuffer || ArrayBuffer.isView(file.bytes)) bytes = file.bytes;
  else throw new OmnisliceError('invalid_option', 'file must be a File, a Blob or {name, bytes}');
  if (signal && signal.aborted) throw new OmnisliceError('cancelled', 'cancelled');
  const engine = slicer || (await sharedSlicer());
  const { meshId } = await engine.loadMesh(fileName, bytes, placementOf(settings));
  try {
    const result = await engine.slice(meshId, settings, { onProgress, signal });
    // Keep the result object itself: its `program` text is decoded lazily on first read.
    result.fileName = programFileName(fileName, result.programExtension);
    return result;
  } finally {
    if (typeof engine.unloadMesh === 'function') engine.unloadMesh(meshId).catch(() => {});
  }
}
