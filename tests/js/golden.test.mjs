// SPDX-License-Identifier: MIT
// Golden programs (issue 24, the Renovation): a fixed set of small cases, every method on every
// machine kind it supports, on generated, project and shared models, sliced by the native CLI and
// by the wasm module. The sha256 of each program (its header's timestamp masked), of each report
// (its timings removed, keys sorted) and, in wasm, of the preview buffers must equal the values in
// tests/fixtures/golden.json.
// Where those values came from is written in the fixture's "recorded" field; they change only with
// a commit that says why. To record them again (after a deliberate change of behaviour):
//   OMNISLICE_GOLDEN_RECORD=1 node --test tests/js/golden.test.mjs
import { describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import crypto from 'node:crypto';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import * as meshes from './fixtures/meshes.js';
import { CI, NATIVE_CLI, REPO, loadShipped, sharedModel, wasmUnavailable } from './wasm-support.mjs';

const FIXTURE = path.join(REPO, 'tests/fixtures/golden.json');
const RECORD = process.env.OMNISLICE_GOLDEN_RECORD === '1';

const why = wasmUnavailable();
if (why && CI) throw new Error(`golden tests cannot run under CI: ${why}`);
const nativeWhy = fs.existsSync(NATIVE_CLI) ? null : `native CLI ${NATIVE_CLI} missing (scripts/build.sh native)`;
if (nativeWhy && CI) throw new Error(nativeWhy);

const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'omnislice-golden-'));
process.on('exit', () => fs.rmSync(tmp, { recursive: true, force: true }));

const sha256 = (data) => crypto.createHash('sha256').update(data).digest('hex');

/** The program with its header's timestamp masked (the only part that depends on the clock). */
export function programDigest(text) {
  return sha256(text.replace(/\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ/, 'TIMESTAMP'));
}

/** A report without what depends on the clock (timings: `timings_ms`, `*_ms`, `ms`), keys sorted. */
export function stripReport(value) {
  if (Array.isArray(value)) return value.map(stripReport);
  if (value === null || typeof value !== 'object') return value;
  const out = {};
  for (const key of Object.keys(value).sort()) {
    if (key === 'timings_ms' || key === 'ms' || key.endsWith('_ms')) continue;
    out[key] = stripReport(value[key]);
  }
  return out;
}

/** The figures shown when a digest differs (the first place to look). */
const FIGURES = ['layers', 'sliced_layers', 'moves', 'path_mm', 'extrusion_mm', 'travel_mm', 'retractions',
  'estimated_time_s'];
function figures(report) {
  return Object.fromEntries(FIGURES.map((k) => [k, report[k]]));
}

/** The model of a case as {name, bytes}, or null when a shared model is absent (skip). */
function model(spec) {
  if (spec.gen) {
    const data = meshes[spec.gen](...spec.args);
    const bytes = typeof data === 'string' ? new TextEncoder().encode(data) : new Uint8Array(data);
    return { name: spec.name, bytes };
  }
  const file = spec.shared ? sharedModel(spec.shared) : path.join(REPO, spec.repo);
  if (!file) return null;
  return { name: path.basename(file), bytes: new Uint8Array(fs.readFileSync(file)) };
}

// A slice refused as unsound (verify) writes no program but its report: status
// 'unsound_program' and program null.
function nativeSlice(c, input) {
  const file = path.join(tmp, `${c.name}-${input.name}`);
  fs.writeFileSync(file, input.bytes);
  const out = path.join(tmp, `${c.name}.program`);
  const report = path.join(tmp, `${c.name}.report.json`);
  fs.rmSync(out, { force: true });
  const args = ['slice', file, '-o', out, '--report', report];
  for (const [k, v] of Object.entries(c.settings)) args.push('--set', `${k}=${v}`);
  let status = 'ok';
  try {
    execFileSync(NATIVE_CLI, args, { stdio: ['ignore', 'pipe', 'pipe'] });
  } catch (e) {
    if (!/error: unsound_program: /.test(String(e.stderr))) throw e;
    status = 'unsound_program';
  }
  return {
    status,
    program: status === 'ok' ? fs.readFileSync(out, 'utf8') : null,
    report: JSON.parse(fs.readFileSync(report, 'utf8')),
  };
}

function wasmSlice(wasm, c, input) {
  try {
    const w = wasm.slice(input.bytes, input.name, c.settings);
    return { status: 'ok', program: w.program, report: w.report, preview: w.preview };
  } catch (e) {
    if (e.code !== 'unsound_program') throw e;
    return { status: e.code, program: null, report: e.report, preview: e.preview };
  }
}

/**
 * The wasm preview's buffers by leaf name, whatever object they are nested in, sorted by name:
 * name, element type and bytes of each (empty buffers left out), so regrouping the preview into
 * per-method sections keeps the digest while any changed value changes it.
 */
export function previewDigest(preview) {
  const leaves = new Map();
  const walk = (value, name) => {
    if (ArrayBuffer.isView(value)) {
      if (value.length > 0) {
        assert.ok(!leaves.has(name), `preview buffer ${name} appears twice`);
        leaves.set(name, value);
      }
    } else if (typeof value === 'number') {
      if (value !== 0) leaves.set(name, new Float32Array([value]));
    } else if (value && typeof value === 'object') {
      for (const [k, v] of Object.entries(value)) walk(v, k);
    }
  };
  walk(preview, '');
  const hash = crypto.createHash('sha256');
  for (const name of [...leaves.keys()].sort()) {
    const v = leaves.get(name);
    hash.update(`${name}:${v.constructor.name}:${v.length};`);
    hash.update(new Uint8Array(v.buffer, v.byteOffset, v.byteLength));
  }
  return hash.digest('hex');
}

function digests(result) {
  const d = {
    status: result.status,
    program_sha256: result.program === null ? null : programDigest(result.program),
    report_sha256: sha256(JSON.stringify(stripReport(result.report))),
  };
  if (result.preview) d.preview_sha256 = previewDigest(result.preview);
  d.figures = figures(result.report);
  return d;
}

const fixture = JSON.parse(fs.readFileSync(FIXTURE, 'utf8'));

describe('golden programs (byte-identical through the Renovation)', { skip: why || nativeWhy || false }, () => {
  let wasm;
  const recorded = [];
  for (const c of fixture.cases) {
    test(`${c.name}`, async (t) => {
      const input = model(c.model);
      if (!input) {
        t.skip('../shared/models absent');
        return;
      }
      wasm ??= (await loadShipped()).module;
      const native = digests(nativeSlice(c, input));
      const inWasm = digests(wasmSlice(wasm, c, input));
      if (RECORD) {
        c.native = native;
        c.wasm = inWasm;
        recorded.push(c.name);
        return;
      }
      for (const [where, got] of [['native', native], ['wasm', inWasm]]) {
        const want = c[where];
        assert.ok(want, `${c.name}: no recorded ${where} values (record them: OMNISLICE_GOLDEN_RECORD=1)`);
        assert.equal(got.status, want.status ?? 'ok', `${c.name} (${where}): status`);
        assert.equal(got.program_sha256, want.program_sha256,
          `${c.name} (${where}): the program changed; figures now ${JSON.stringify(got.figures)}, ` +
          `recorded ${JSON.stringify(want.figures)}`);
        assert.equal(got.report_sha256, want.report_sha256,
          `${c.name} (${where}): the report changed; figures now ${JSON.stringify(got.figures)}, ` +
          `recorded ${JSON.stringify(want.figures)}`);
        assert.equal(got.preview_sha256, want.preview_sha256, `${c.name} (${where}): the preview changed`);
      }
    });
  }
  test('record', { skip: !RECORD }, () => {
    const head = execFileSync('git', ['rev-parse', '--short', 'HEAD'], { cwd: REPO, encoding: 'utf8' }).trim();
    const dirty = execFileSync('git', ['status', '--porcelain', '--', 'core', 'wasm'], { cwd: REPO, encoding: 'utf8' })
      .trim() !== '';
    fixture.recorded = `${new Date().toISOString().slice(0, 10)}: core and wasm of commit ${head}` +
      `${dirty ? ' with uncommitted changes' : ''}, native CLI and wasm module (${recorded.length} cases)`;
    fs.writeFileSync(FIXTURE, `${JSON.stringify(fixture, null, 1)}\n`);
  });
});
