// SPDX-License-Identifier: MIT
// Shared by the Node tests of the wasm module: where the artefacts are, and loading them.
import fs from 'node:fs';
import path from 'node:path';
import { pathToFileURL } from 'node:url';
import { REPO } from './static-server.mjs';

export { REPO };
export const WASM_DIR = process.env.OMNISLICE_WASM_DIR
  ? path.resolve(process.env.OMNISLICE_WASM_DIR) : path.join(REPO, 'build/wasm');
export const NATIVE_CLI = process.env.OMNISLICE_CLI || path.join(REPO, 'build/native/omnislice');
export const SHARED_MODELS = path.resolve(REPO, '../shared/models');
export const CI = process.env.CI === 'true';

/** Why the wasm module cannot be tested, or null (the caller fails under CI). */
export function wasmUnavailable() {
  for (const f of ['omnislice.mjs', 'omnislice.wasm', 'omnislice.js']) {
    if (!fs.existsSync(path.join(WASM_DIR, f))) return `${f} missing in ${WASM_DIR} (run scripts/build-wasm.sh)`;
  }
  return null;
}

/** Load the shipped wrapper + module from WASM_DIR (Node passes wasmBinary). */
export async function loadShipped() {
  const wrapper = await import(pathToFileURL(path.join(WASM_DIR, 'omnislice.js')).href);
  const module = await wrapper.loadOmnislice({
    moduleUrl: pathToFileURL(path.join(WASM_DIR, 'omnislice.mjs')).href,
    wasmBinary: fs.readFileSync(path.join(WASM_DIR, 'omnislice.wasm')),
  });
  return { wrapper, module };
}

/** The shared models folder, or null when absent (a skip message; a failure under CI). */
export function sharedModel(name) {
  const file = path.join(SHARED_MODELS, name);
  if (fs.existsSync(file)) return file;
  if (CI) throw new Error(`shared model ${file} is required under CI=true`);
  return null;
}
