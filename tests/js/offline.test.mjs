// SPDX-License-Identifier: MIT
// The offline app's files: web/sw.js precaches exactly the files the app serves (every file of
// web/ but the service worker itself and type declarations, the workers, the wasm engine, the three.js modules the page
// imports), each of which the app's server resolves to a file; the manifest names the start page
// and two PNG icons of its sizes; the icons are what scripts/make-icons.mjs draws.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';

import { ROUTES, resolveRequestPath } from '../../scripts/serve.mjs';
import { ICON_SIZES, iconPng } from '../../scripts/make-icons.mjs';
import { REPO } from './static-server.mjs';

const IN_CI = process.env.CI === 'true';

/** APP_FILES of web/sw.js. */
function precacheList() {
  const text = fs.readFileSync(path.join(REPO, 'web', 'sw.js'), 'utf8');
  const m = text.match(/const APP_FILES = \[([\s\S]*?)\];/);
  assert.ok(m, 'web/sw.js declares APP_FILES');
  return [...m[1].matchAll(/'([^']*)'/g)].map((x) => x[1]);
}

function filesUnder(dir, prefix) {
  const out = [];
  for (const entry of fs.readdirSync(dir, { withFileTypes: true })) {
    const full = path.join(dir, entry.name);
    if (entry.isDirectory()) out.push(...filesUnder(full, `${prefix}${entry.name}/`));
    else out.push(`${prefix}${entry.name}`);
  }
  return out;
}

test('sw.js precaches every file the app serves, and only those', () => {
  const list = precacheList();
  assert.equal(new Set(list).size, list.length, 'no file twice');
  const expected = new Set(['/']);
  // (Type declarations are for the package's users, not loaded by the app.)
  for (const f of filesUnder(path.join(REPO, 'web'), '/')) if (f !== '/sw.js' && !f.endsWith('.d.ts')) expected.add(f);
  for (const f of filesUnder(path.join(REPO, 'workers'), '/workers/')) if (f.endsWith('.js')) expected.add(f);
  for (const f of ['omnislice.js', 'omnislice.mjs', 'omnislice.wasm']) expected.add(`/wasm/${f}`);
  // What the page imports of three.js: the module, its core, the orbit controls.
  for (const f of ['build/three.module.js', 'build/three.core.js', 'examples/jsm/controls/OrbitControls.js']) {
    expected.add(`/vendor/three/${f}`);
  }
  assert.deepEqual([...list].sort(), [...expected].sort());
  // three.module.js imports nothing else of three.
  const three = fs.readFileSync(path.join(REPO, 'node_modules/three/build/three.module.js'), 'utf8');
  const imported = [...three.matchAll(/from '\.\/([^']+)'/g)].map((x) => x[1]);
  assert.deepEqual([...new Set(imported)], ['three.core.js']);
});

test('every precached path resolves to a served file', (t) => {
  const wasmBuilt = fs.existsSync(path.join(REPO, 'build/wasm/omnislice.wasm'));
  if (!wasmBuilt && !IN_CI) t.diagnostic('no wasm build: its three files not checked');
  for (const url of precacheList()) {
    if (url.startsWith('/wasm/') && !wasmBuilt && !IN_CI) continue;
    const r = resolveRequestPath(url === '/' ? '/index.html' : url, REPO, ROUTES);
    assert.ok(r.file, `${url}: ${JSON.stringify(r)}`);
    assert.ok(fs.statSync(r.file).isFile(), url);
  }
});

test('manifest: start page, standalone display, two PNG icons of their stated sizes', () => {
  const m = JSON.parse(fs.readFileSync(path.join(REPO, 'web', 'manifest.webmanifest'), 'utf8'));
  assert.equal(m.name, 'Omnislice');
  assert.equal(m.start_url, '/');
  assert.equal(m.display, 'standalone');
  assert.deepEqual(m.icons.map((i) => i.sizes), ['192x192', '512x512']);
  for (const icon of m.icons) {
    const bytes = fs.readFileSync(path.join(REPO, 'web', icon.src));
    assert.deepEqual([...bytes.subarray(0, 8)], [0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a], icon.src);
    assert.equal(bytes.toString('ascii', 12, 16), 'IHDR');
    const [w, h] = icon.sizes.split('x').map(Number);
    assert.equal(bytes.readUInt32BE(16), w, icon.src);
    assert.equal(bytes.readUInt32BE(20), h, icon.src);
    assert.equal(icon.type, 'image/png');
  }
});

test('the committed icons are the generator output (drawn by the project, deterministic)', () => {
  for (const size of ICON_SIZES) {
    const committed = fs.readFileSync(path.join(REPO, 'web', 'icons', `icon-${size}.png`));
    assert.ok(committed.equals(iconPng(size)), `icon-${size}.png differs from scripts/make-icons.mjs`);
  }
});
