// SPDX-License-Identifier: MIT
// The page's settings fields as the page builds them at start-up (web/main.js): settingsFields()
// over the core's settings table, read here from the shipped wasm module, so the Node and e2e
// tests see the real defaults, ranges and choices. Without the module the tests that need the
// fields skip (fieldsUnavailable), except under CI=true, where that is a failure.
import { CI, loadShipped, wasmUnavailable } from './wasm-support.mjs';
import { settingsFields } from '../../web/settings-fields.js';
import { SettingsModel } from '../../web/settings-panel.js';

/** Why the fields cannot be built here, or false (the skip option of node:test). */
export const fieldsUnavailable = wasmUnavailable() ? `skipped: ${wasmUnavailable()}` : false;
if (fieldsUnavailable && CI) throw new Error(`the page's settings fields need the wasm module under CI: ${fieldsUnavailable}`);

let schema = null;

/** The core's settings table (module.settingsSchema()), loaded once per test file. */
export async function coreSettingsSchema() {
  if (!schema) schema = (await loadShipped()).module.settingsSchema();
  return schema;
}

/** The page's settings fields over the core's table (settingsFields). */
export async function pageFields() {
  return settingsFields(await coreSettingsSchema());
}

/** A fresh SettingsModel at the core's defaults, as the page makes it. */
export async function newSettingsModel() {
  return new SettingsModel(await pageFields());
}
