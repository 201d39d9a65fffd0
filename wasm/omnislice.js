// SPDX-License-Identifier: MIT
// JS wrapper over the raw embind module (omnislice.mjs): defaults, validation, JSON parsing and
// typed errors. Works in browsers, workers and Node (Node reads omnislice.wasm itself when no
// wasmBinary is given). The build copies this file next to omnislice.mjs (build/wasm/).

/** Status codes of core/common/status.cpp, plus the JS-only 'cancelled'/'worker_failed'. */
export const STATUS_CODES = Object.freeze([
  'ok', 'empty_input', 'unsupported_format', 'parse_error', 'truncated_file',
  'non_finite_vertex', 'degenerate_input', 'open_mesh', 'non_manifold', 'self_intersecting',
  'invalid_option', 'io_error', 'cancelled', 'unsound_program', 'out_of_memory', 'internal',
  'worker_failed',
]);

/** The memory budget verify uses when none is given (setting memory_mb's default), MB. */
export const DEFAULT_MEMORY_MB = 2048;

/** The one error class of the JS side: `code` is one of STATUS_CODES (never 'ok'). */
export class OmnisliceError extends Error {
  /** @param {string} code @param {string} message */
  constructor(code, message) {
    super(message || code);
    this.name = 'OmnisliceError';
    this.code = STATUS_CODES.includes(code) && code !== 'ok' ? code : 'internal';
  }
}

// Node, its worker threads included (omnislice/node runs the browser worker there with a `self`
// of its own); a browser's worker has WorkerGlobalScope, which Node does not define.
const isNode = typeof process !== 'undefined' && !!process.versions && !!process.versions.node
  && typeof window === 'undefined' && typeof WorkerGlobalScope === 'undefined';

/**
 * Settings object -> "key=value" lines for setSetting(). Numbers must be finite; arrays are
 * joined with ',' (e.g. direction [0,0,1]); booleans are 'true'/'false'; null/undefined skipped.
 * @param {Record<string, number|string|boolean|number[]>} settings
 * @returns {string}
 */
export function settingsToLines(settings = {}) {
  if (settings === null || typeof settings !== 'object' || Array.isArray(settings)) {
    throw new OmnisliceError('invalid_option', 'settings must be an object of key -> value');
  }
  const lines = [];
  for (const [key, value] of Object.entries(settings)) {
    if (value === undefined || value === null) continue;
    if (!key || /[=\n\r]/.test(key)) {
      throw new OmnisliceError('invalid_option', `invalid setting key "${key}"`);
    }
    let text;
    if (typeof value === 'number') {
      if (!Number.isFinite(value)) {
        throw new OmnisliceError('invalid_option', `setting ${key}: ${value} is not a finite number`);
      }
      text = String(value);
    } else if (typeof value === 'boolean') {
      text = value ? 'true' : 'false';
    } else if (Array.isArray(value)) {
      if (!value.every((v) => typeof v === 'number' && Number.isFinite(v))) {
        throw new OmnisliceError('invalid_option', `setting ${key}: array values must be finite numbers`);
      }
      text = value.join(',');
    } else if (typeof value === 'string') {
      text = value;
    } else {
      throw new OmnisliceError('invalid_option', `setting ${key}: unsupported value type ${typeof value}`);
    }
    if (/[\n\r]/.test(text)) {
      throw new OmnisliceError('invalid_option', `setting ${key}: value contains a line break`);
    }
    lines.push(`${key}=${text}`);
  }
  return lines.join('\n');
}

function toBytes(bytes, what) {
  if (bytes instanceof Uint8Array) return bytes;
  if (bytes instanceof ArrayBuffer) return new Uint8Array(bytes);
  if (ArrayBuffer.isView(bytes)) return new Uint8Array(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  throw new OmnisliceError('invalid_option', `${what} must be an ArrayBuffer or Uint8Array`);
}

function parseJson(text, what) {
  if (!text) return {};
  try {
    return JSON.parse(text);
  } catch (e) {
    throw new OmnisliceError('internal', `${what} is not valid JSON: ${e.message}`);
  }
}

// The core calls back with (stage, fraction) or, when a search level is done, (stage, fraction,
// search {line, level, J_G, beams}).
function progressAdapter(onProgress) {
  if (typeof onProgress !== 'function') return undefined;
  return (stage, fraction, search) => onProgress(search ? { stage, fraction, search } : { stage, fraction }) !== false;
}

/**
 * Load the module.
 * @param {{wasmBinary?: ArrayBuffer|Uint8Array, locateFile?: (name: string, prefix: string) => string,
 *          moduleUrl?: string|URL, factory?: Function}} [options]
 *   moduleUrl: URL of omnislice.mjs (default: next to this file); factory: an already imported
 *   Emscripten factory (skips the import).
 * @returns {Promise<Omnislice>}
 */
export async function loadOmnislice(options = {}) {
  const { locateFile } = options;
  let { wasmBinary, factory, moduleUrl } = options;
  const url = new URL(moduleUrl ?? './omnislice.mjs', import.meta.url);
  if (!factory) factory = (await import(url.href)).default;
  if (typeof factory !== 'function') {
    throw new OmnisliceError('internal', 'omnislice.mjs does not export a module factory');
  }
  if (!wasmBinary && !locateFile && isNode && url.protocol === 'file:') {
    const fs = await import('node:fs');
    wasmBinary = fs.readFileSync(new URL('./omnislice.wasm', url));
  }
  const moduleArgs = {};
  if (wasmBinary) moduleArgs.wasmBinary = wasmBinary;
  if (locateFile) moduleArgs.locateFile = locateFile;
  else moduleArgs.locateFile = (name) => new URL(name, url).href;
  let raw;
  try {
    raw = await factory(moduleArgs);
  } catch (e) {
    throw new OmnisliceError('internal', `cannot instantiate the wasm module: ${e && e.message || e}`);
  }
  return new Omnislice(raw);
}

/** A loaded module. Calls are synchronous (run them in a worker in a page). */
export class Omnislice {
  constructor(raw) {
    /** The raw embind module (`_slice`, `_info`, `_verify`, `_defaultSettings`). */
    this.raw = raw;
    /** Set after a wasm abort: the instance must be discarded. */
    this.aborted = false;
  }

  /**
   * Run a raw call; a non-ok status throws OmnisliceError. details(out), when given, returns
   * fields to attach to that error (an unsound slice keeps its report and preview).
   */
  #call(fn, details) {
    if (this.aborted) throw new OmnisliceError('internal', 'the wasm module aborted earlier; load it again');
    let out;
    try {
      out = fn();
    } catch (e) {
      if (e instanceof OmnisliceError) throw e;
      this.aborted = true;  // RuntimeError / abort(): the instance state is undefined now
      const err = new OmnisliceError('internal', `wasm crashed: ${e && e.message || e}`);
      err.fatal = true;
      throw err;
    }
    if (out.status !== 'ok') {
      const err = new OmnisliceError(out.status, out.message);
      if (details) Object.assign(err, details(out));
      throw err;
    }
    return out;
  }

  /**
   * Slice a mesh file.
   * @param {ArrayBuffer|Uint8Array} bytes file content
   * @param {string} name file name (extension picks the format)
   * @param {object} [settings] setting key -> value
   * @param {{onProgress?: (p: {stage: string, fraction: number, search?: object}) => (boolean|void),
   *          programAs?: 'string'|'bytes'}} [options] onProgress: search {line, level, J_G,
   *   beams} when a level of the multidir plane search is done (workers/protocol.js
   *   SEARCH_LINES); returning false cancels
   */
  slice(bytes, name, settings = {}, { onProgress, programAs = 'string' } = {}) {
    const data = toBytes(bytes, 'bytes');
    const lines = settingsToLines(settings);
    // unsound_program: the program was refused, but the error keeps what says why and where.
    const unsound = (o) => (o.status === 'unsound_program'
      ? { report: parseJson(o.report, 'report'), info: parseJson(o.info, 'info'), preview: o.preview, mesh: o.mesh }
      : {});
    const out = this.#call(() => this.raw._slice(data, String(name ?? ''), lines, progressAdapter(onProgress)), unsound);
    return {
      program: programAs === 'bytes' ? out.program : new TextDecoder().decode(out.program),
      report: parseJson(out.report, 'report'),
      info: parseJson(out.info, 'info'),
      layers: out.layers,
      preview: out.preview,
      programExtension: out.programExtension || 'gcode',
      mesh: out.mesh,
    };
  }

  /**
   * method = auto in a pool of workers (workers/auto-pool.js): the candidates for this mesh and
   * machine (core pipeline.h planAuto).
   * @returns {{candidates: {method: string, settings: object}[], rerun_settings: object}} slice
   *   candidate k with the settings changed by its `settings`
   */
  autoPlan(bytes, name, settings = {}) {
    const data = toBytes(bytes, 'bytes');
    const out = this.#call(() => this.raw._autoPlan(data, String(name ?? ''), settingsToLines(settings)));
    return parseJson(out.plan, 'auto plan');
  }

  /**
   * method = auto's choice over the candidates sliced so far (core pipeline.h chooseAuto).
   * @param {object} settings the user's settings
   * @param {{method: string, status: string, message?: string, ms?: number, full?: boolean,
   *   report?: object|null}[]} candidates in the plan's order
   * @returns {{rerun: number} | {chosen: number, status: string, message: string, auto: object}}
   */
  autoChoose(settings, candidates) {
    if (!Array.isArray(candidates)) throw new OmnisliceError('invalid_option', 'candidates must be an array');
    const texts = candidates.map((c) => JSON.stringify(c));
    const out = this.#call(() => this.raw._autoChoose(settingsToLines(settings), texts));
    return parseJson(out.decision, 'auto decision');
  }

  /**
   * Read, validate and place a mesh (placement keys only).
   * @returns {{info: object, mesh: {positions: Float32Array, indices: Uint32Array}}}
   */
  info(bytes, name, placement = {}, { onProgress } = {}) {
    const data = toBytes(bytes, 'bytes');
    const lines = settingsToLines(placement);
    const out = this.#call(() => this.raw._info(data, String(name ?? ''), lines, progressAdapter(onProgress)));
    return { info: parseJson(out.info, 'info'), mesh: out.mesh };
  }

  /** Verify a program (G-code text) against its mesh; returns the verification report object. */
  verify(program, meshBytes, meshName, { onProgress, memoryMb = DEFAULT_MEMORY_MB } = {}) {
    if (typeof program !== 'string') throw new OmnisliceError('invalid_option', 'program must be a string');
    if (!(Number.isFinite(memoryMb) && memoryMb >= 16)) {
      throw new OmnisliceError('invalid_option', `memoryMb must be a number of MB >= 16, got ${memoryMb}`);
    }
    const data = toBytes(meshBytes, 'meshBytes');
    const out = this.#call(() => this.raw._verify(program, data, String(meshName ?? ''), progressAdapter(onProgress), memoryMb));
    return parseJson(out.verify, 'verify report');
  }

  /**
   * Check a machine profile JSON (a user's profile file; schema in docs/MACHINES.md) with the
   * core's parser. Throws OmnisliceError 'parse_error' with the core's message when it is malformed.
   * @param {string} text the JSON text
   * @returns {{profile: object, json: string}} the profile as the program header writes it (one
   *   line, usable as the `machine_json` setting) and parsed
   */
  parseMachine(text) {
    if (typeof text !== 'string') throw new OmnisliceError('invalid_option', 'machine JSON must be a string');
    const out = this.#call(() => this.raw._parseMachine(text));
    return { profile: parseJson(out.json, 'machine JSON'), json: out.json };
  }

  /**
   * Replay a program (G-code, robot CSV or URScript written by Omnislice) through its declared
   * machine, for the machine animation.
   * @param {string} program the program text
   * @returns {{profile: object, format: string, layers: number, preview: {positions: Float32Array,
   *   features: Uint8Array, layers: Uint32Array, machine: Float32Array}}}
   */
  replay(program) {
    if (typeof program !== 'string') throw new OmnisliceError('invalid_option', 'program must be a string');
    const out = this.#call(() => this.raw._replay(program));
    return { profile: parseJson(out.machine, 'machine JSON'), format: out.format, layers: out.layers, preview: out.preview };
  }

  /**
   * The built-in machine profiles, in display order, sized by the settings' bed_size and nozzle.
   * @param {object} [settings] setting key -> value
   * @returns {{name: string, profile: object, json: string}[]}
   */
  machines(settings = {}) {
    const lines = settingsToLines(settings);
    const out = this.#call(() => this.raw._machines(lines));
    const list = [];
    for (let i = 0; i < out.machines.length; i++) {
      const { name, json } = out.machines[i];
      list.push({ name, json, profile: parseJson(json, `machine ${name}`) });
    }
    return list;
  }

  /**
   * The settings table (core/pipeline/settings_table.cpp), in listing order: [{key, type
   * ('number' | 'integer' | 'boolean' | 'choice' | 'vector' | 'text'), default (text), min, max
   * (number, integer), unit, help, choices (choice, boolean), method (listed only with it)}].
   */
  settingsSchema() {
    const out = this.#call(() => ({ status: 'ok', schema: this.raw._settingsSchema() }));
    return parseJson(out.schema, 'settings schema');
  }

  /**
   * The instance's memory: {heapBytes (the wasm linear memory; it only grows), usedBytes (what
   * malloc holds: the figure a leak raises), blocks (free chunks)}.
   */
  heapStats() {
    const { heapBytes, usedBytes, blocks } = this.#call(() => ({ status: 'ok', ...this.raw._heapStats() }));
    return { heapBytes, usedBytes, blocks };
  }

  /** Default settings: {values: {key: text}, keys: [...]} in the core's stable order. */
  defaultSettings() {
    const { values, keys } = this.#call(() => ({ status: 'ok', ...this.raw._defaultSettings() }));
    return { values, keys };
  }
}
