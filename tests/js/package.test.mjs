// SPDX-License-Identifier: MIT
// The npm package (scripts/pack.mjs): packed, installed from the tarball into an empty project
// (nothing else copied, no network), and used from Node through omnislice/node on a shared model:
// the program equals the one the wasm module gives in this process for the same file and settings
// (the header's date aside). The browser entry and the types resolve from the installed package.
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';

import { pack, packageJson } from '../../scripts/pack.mjs';
import { loadShipped, sharedModel } from './wasm-support.mjs';

const CI = process.env.CI === 'true';
const MODEL = 'compas_overhang_coin_closed_low_res.stl';
const SETTINGS = { layer_height: 0.3, fit_mm: 30, machine: 'table5', method: 'multidir' };
let dir = null;
let why = null;

before(() => {
  if (!fs.existsSync(path.resolve('build/wasm/omnislice.wasm'))) {
    why = 'no wasm build (npm run build:wasm)';
    if (CI) throw new Error(why);
    return;
  }
  dir = fs.mkdtempSync(path.join(os.tmpdir(), 'omnislice-package-'));
});

after(() => {
  if (dir) fs.rmSync(dir, { recursive: true, force: true });
});

test('the tarball installs into an empty project and slices a shared model from Node', async (t) => {
  if (why) return t.skip(why);
  const file = sharedModel(MODEL);
  if (!file) return t.skip(`shared model ${MODEL} not found`);
  const tarball = pack({ outDir: dir });
  assert.equal(path.basename(tarball), `omnislice-${packageJson().version}.tgz`);
  const listing = execFileSync('tar', ['tzf', tarball], { encoding: 'utf8' }).split('\n').filter(Boolean);
  for (const f of ['package/node/index.mjs', 'package/wasm/omnislice.wasm', 'package/workers/slicer-worker.js',
    'package/web/omnislice-embed.js', 'package/web/omnislice-embed.d.ts', 'package/node/index.d.ts']) {
    assert.ok(listing.includes(f), `${f} in the tarball`);
  }
  assert.ok(!listing.some((f) => f.includes('/core/') || f.endsWith('.cpp')), 'no sources of the core');

  const project = path.join(dir, 'consumer');
  fs.mkdirSync(project);
  fs.writeFileSync(path.join(project, 'package.json'), JSON.stringify({ name: 'consumer', private: true, type: 'module' }));
  execFileSync('npm', ['install', '--offline', '--no-audit', '--no-fund', '--ignore-scripts', tarball],
    { cwd: project, stdio: ['ignore', 'ignore', 'inherit'] });
  fs.writeFileSync(path.join(project, 'run.mjs'), `
import fs from 'node:fs';
import { sliceFile, disposeSharedSlicer, OmnisliceError } from 'omnislice/node';
const settings = JSON.parse(process.argv[3]);
const stages = new Set();
const t0 = Date.now();
const r = await sliceFile(process.argv[2], settings, { onProgress: (p) => stages.add(p.stage) });
fs.writeFileSync('program.txt', r.programBytes);
let refused = null;
try { await sliceFile('missing.stl', {}); } catch (e) { refused = { code: e.code, isError: e instanceof OmnisliceError }; }
await disposeSharedSlicer();
console.log(JSON.stringify({ fileName: r.fileName, layers: r.report.layers, stages: [...stages], ms: Date.now() - t0, refused,
  browserEntry: import.meta.resolve('omnislice'), engine: import.meta.resolve('omnislice/workers/engine.js') }));
`);
  const out = JSON.parse(execFileSync(process.execPath, ['run.mjs', file, JSON.stringify(SETTINGS)],
    { cwd: project, encoding: 'utf8', timeout: 300_000 }).trim().split('\n').pop());
  t.diagnostic(`omnislice/node: ${MODEL} sliced in ${out.ms} ms (${out.layers} layers); stages ${out.stages.join(' ')}`);
  assert.equal(out.fileName, MODEL.replace(/\.stl$/, '.gcode'));
  assert.ok(out.stages.includes('program'), 'progress reached the program stage');
  assert.deepEqual(out.refused, { code: 'io_error', isError: true });
  assert.ok(out.browserEntry.endsWith('/node_modules/omnislice/web/omnislice-embed.js'), out.browserEntry);
  assert.ok(out.engine.endsWith('/node_modules/omnislice/workers/engine.js'), out.engine);

  // The same program as the wasm module in this process.
  const { module } = await loadShipped();
  const direct = module.slice(new Uint8Array(fs.readFileSync(file)), MODEL, SETTINGS);
  const fromPackage = fs.readFileSync(path.join(project, 'program.txt'), 'utf8');
  const body = (text) => text.slice(text.indexOf('\n') + 1);
  assert.equal(direct.report.layers, out.layers);
  assert.equal(body(fromPackage), body(direct.program));
});
