// SPDX-License-Identifier: MIT
// The worker message protocol: every message type between the engine facade (engine.js, main
// thread) and the slicer worker (slicer-worker.js), in one place.
//
// Request (main -> worker):  {id: number, type: RequestType, payload: object}
// Reply   (worker -> main):  {id, type: 'ready'|'progress'|'result'|'error', ...}
//   ready:    {id, type: 'ready', version}                      answers `init`, before any work
//   progress: {id, type: 'progress', stage, fraction, search?}  interim; stages in pipeline order,
//                                                               fraction nondecreasing per stage;
//                                                               search: a level of the multidir
//                                                               plane search is done (stage
//                                                               'decompose'; see SEARCH_LINES)
//   result:   {id, type: 'result', result}                      ArrayBuffers inside are transferred
//   error:    {id, type: 'error', code, message, fatal}         code: a STATUS_CODES string;
//                                                               fatal: the worker must be discarded
//                                                               (the facade also replaces it after
//                                                               out_of_memory: its heap stays grown);
//                                                               unsound_program also carries the
//                                                               refused slice's report, info,
//                                                               preview and mesh
// A mesh is sent once (`load`, with a facade-chosen meshId) and referenced by meshId after that.
// Cancel is not a message: the facade terminates the worker and spawns a new one.

export { OmnisliceError, STATUS_CODES } from '../wasm/omnislice.js';

/** Protocol version sent in `ready`. */
export const PROTOCOL_VERSION = 1;

/** Request types (main -> worker). */
export const Request = Object.freeze({
  /** payload {wasmUrl?: string}: load the wasm module. Reply: `ready` {version}. */
  INIT: 'init',
  /** payload {meshId, name, bytes: ArrayBuffer (transferred), placement: object}: keep the mesh
   *  bytes under meshId; read/validate/place it. Reply: `result` {meshId, info: object,
   *  mesh: {positions: Float32Array, indices: Uint32Array}} (buffers transferred). */
  LOAD: 'load',
  /** payload {meshId}: forget a mesh. Reply: `result` {meshId}. */
  UNLOAD: 'unload',
  /** payload {meshId | file: {name, bytes}, placement?}: read/validate/place. Reply: `result`
   *  {info, mesh} (buffers transferred). */
  INFO: 'info',
  /** payload {meshId | file: {name, bytes}, settings: object}: slice (the mesh's load placement
   *  is applied first, settings override it). Reply: `progress`*, then `result` {program:
   *  ArrayBuffer (UTF-8 program: G-code, robot CSV or URScript), programExtension: 'gcode' |
   *  'csv' | 'script', report: object, info: object, layers: number, preview: {positions,
   *  features, layers, machine, axes, poses, surfacePositions, surfaceTriangles, surfaceLayers,
   *  missedVoxels, supportVoxels, voxelWidth, curves, fieldPositions, fieldTriangles,
   *  fieldValues, nodePositions, nodeLayers, treeEdges, sequence, skippedSegments,
   *  skippedLayers, partPositions, partTriangles, partIds, riskyBefore, riskyAfter,
   *  unsupportedPoints, collisionPoints}
   *  (core/pipeline/preview.h SlicePreview, flattened; the curved-layer, voxel, geodesic and multidir
   *  buffers are empty for other methods; poses: #S*7 platform pose per segment end, quaternion
   *  x y z w and translation, part frame -> machine frame; curves: #S 1-based NL curve index per segment, 0 =
   *  none, empty unless the iso-planar fill ran; field*: the boundary surface with the geodesic
   *  distance per vertex; node* and treeEdges: the skeleton tree; sequence: node indices in print
   *  order; skippedSegments: #K*6 ends of the tool path left out where no nozzle axis clears the
   *  part, skippedLayers: #K their layers; part*: the multidir parts' closed meshes with the print
   *  index per triangle; risky*: Uint8 flag per triangle of mesh, risky along +Z (before) and in
   *  its part (after); unsupportedPoints, collisionPoints: #*3 tips of the simulated program's
   *  unsupported and colliding samples, at most 4000 each, empty with verify = off), mesh:
   *  {positions, indices}}
   *  (all buffers transferred). */
  SLICE: 'slice',
  /** payload {meshId | file: {name, bytes}, settings: object}: method = auto's candidates for
   *  this mesh and machine (wasm/omnislice.js autoPlan), for a pool of workers (auto-pool.js).
   *  Reply: `result` {plan: {candidates: [{method, settings}], rerun_settings}}. */
  AUTO_PLAN: 'auto-plan',
  /** payload {settings: object, candidates: [{method, status, message, ms, full, report}]}:
   *  method = auto's choice over them (wasm/omnislice.js autoChoose). Reply: `result`
   *  {decision: {rerun} | {chosen, status, message, auto}}. */
  AUTO_CHOOSE: 'auto-choose',
  /** payload {program: string, meshId | file: {name, bytes}, memoryMb?}: verify by simulation. Reply:
   *  `progress`*, then `result` {report: object}. */
  VERIFY: 'verify',
  /** payload {program: string}: replay a program through its declared machine. Reply: `result`
   *  {profile: object, format, layers, preview: {positions, features, layers, machine, poses}}
   *  (buffers transferred). */
  REPLAY: 'replay',
  /** payload {settings?: object}: the built-in machine profiles. Reply: `result` {machines:
   *  [{name, profile: object, json: string}...]} in display order. */
  MACHINES: 'machines',
  /** payload {}: the core's settings table. Reply: `result` {schema: [{key, type, default, min,
   *  max, unit, help, choices, method}...]} in listing order (wasm/omnislice.js settingsSchema). */
  SETTINGS: 'settings',
  /** payload {json: string}: check a machine profile JSON with the core's parser. Reply: `result`
   *  {profile: object, json: string (one line, for the machine_json setting)}, or `error`
   *  {code: 'parse_error', message}. */
  PARSE_MACHINE: 'parse-machine',
  /** payload {}: the worker's memory and work so far. Reply: `result` {heapBytes (wasm linear
   *  memory), usedBytes (held by malloc), blocks, jobs (requests this worker has answered, this
   *  one and init not counted)} (wasm/omnislice.js heapStats). */
  STATS: 'stats',
  /** Test hook, payload {}: aborts the wasm instance. Reply: `error` {code: 'internal', fatal}. */
  DEBUG_CRASH: 'debug-crash',
});

/**
 * Lines of the `search` of a progress reply {line, level, J_G, beams} (core/common/progress.h
 * SearchLevelProgress), one reply per level of each search line; never throttled.
 *   line:  'greedy' | 'constrained' | 'beam' (the lines of the beam scheme, in that order; one of
 *          them alone for the greedy schemes) | 'screen' (4dof axis search: the constrained line
 *          per axis on a coarse grid, ranking the axes) | 'chosen' (last: the returned sequence,
 *          levels 0..N, J_G exact after refinement = report.multidir.search.J_G_per_level)
 *   level: planes in the line's sequences at this level, 0 = the uncut model (J_G before)
 *   J_G:   mm²; search lines: the least J_G the line reached with at most `level` planes
 *          (nonincreasing along a line); 'chosen': J_G after the first `level` planes
 *   beams: sequences the line goes on extending after this level (0: the line ends here)
 * Levels >= 1 of the search lines number report.multidir.search.levels in all.
 */
export const SEARCH_LINES = Object.freeze(['greedy', 'constrained', 'beam', 'screen', 'chosen']);

/** Reply types (worker -> main). */
export const Reply = Object.freeze({
  READY: 'ready',
  PROGRESS: 'progress',
  RESULT: 'result',
  ERROR: 'error',
});

/** The ArrayBuffers of typed arrays (deduplicated, non-shared) for a transfer list. */
export function transferList(...arrays) {
  const out = [];
  for (const a of arrays) {
    const buffer = a instanceof ArrayBuffer ? a : a && a.buffer;
    if (buffer instanceof ArrayBuffer && !out.includes(buffer)) out.push(buffer);
  }
  return out;
}

/** An error reply for request id from any thrown value. */
export function errorReply(id, error) {
  const code = error && typeof error.code === 'string' ? error.code : 'internal';
  const message = error && error.message ? error.message : String(error);
  const reply = { id, type: Reply.ERROR, code, message, fatal: !!(error && error.fatal) };
  // unsound_program: the refused slice's report, info, preview and mesh (what says why and where).
  for (const key of ['report', 'info', 'preview', 'mesh']) {
    if (error && error[key] !== undefined) reply[key] = error[key];
  }
  return reply;
}
