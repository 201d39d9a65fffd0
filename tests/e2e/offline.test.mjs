// SPDX-License-Identifier: MIT
// The app offline (web/sw.js): after a first visit whose service worker has cached the app, the
// network is cut; a reload loads the page, its engine and the demo from the cache and slices it
// (the same report as online), and a file the app never had fails as a network error would.
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';

import { IN_CI, ROOT } from './page-controls.mjs';
import { browserUnavailable, openPage } from '../js/browser.mjs';

let session = null;
let skipWhy = null;

before(async () => {
  skipWhy = await browserUnavailable();
  if (skipWhy) {
    if (IN_CI) throw new Error(`offline e2e prerequisites: ${skipWhy}`);
    return;
  }
  session = await openPage('/', { root: ROOT, viewport: { width: 1280, height: 800 }, serviceWorkers: 'allow' });
});

after(async () => {
  if (session) await session.close();
});

const waitDone = (page) => page.waitForFunction(
  () => document.body.dataset.state === 'done' || document.body.dataset.state === 'error', null, { timeout: 180_000 });

test('after the first visit the app reloads and slices the demo with the network gone', async (t) => {
  if (skipWhy) return t.skip(skipWhy);
  const { page, context } = session;
  await waitDone(page);
  assert.equal(await page.evaluate(() => document.body.dataset.state), 'done');
  const online = await page.evaluate(() => window.omnislice.report);
  // The worker installed: every app file in its cache, and it controls the page.
  const cached = await page.evaluate(async () => {
    const reg = await navigator.serviceWorker.ready;
    const keys = await caches.keys();
    const cache = await caches.open(keys.find((k) => k.startsWith('omnislice-app-')));
    return { active: !!reg.active, scope: reg.scope, entries: (await cache.keys()).map((r) => new URL(r.url).pathname) };
  });
  assert.ok(cached.active);
  for (const f of ['/', '/main.js', '/workers/slicer-worker.js', '/wasm/omnislice.wasm', '/models/demo-arms.obj', '/models/demo-overhang.stl']) {
    assert.ok(cached.entries.includes(f), `${f} cached (${cached.entries.length} entries)`);
  }
  await context.setOffline(true);
  try {
    const t0 = Date.now();
    await page.reload();
    await waitDone(page);
    const state = await page.evaluate(() => document.body.dataset.state);
    assert.equal(state, 'done', await page.evaluate(() => document.querySelector('[data-testid="error-message"]')?.textContent));
    assert.ok(await page.evaluate(() => !!navigator.serviceWorker.controller), 'the reloaded page is controlled');
    const offline = await page.evaluate(() => window.omnislice.report);
    t.diagnostic(`offline reload and demo slice in ${Date.now() - t0} ms; ${cached.entries.length} cached files`);
    assert.equal(offline.layers, online.layers);
    assert.equal(offline.machine_kind, online.machine_kind);
    assert.equal(offline.estimated_time_s, online.estimated_time_s);
    // Not in the cache and no network: a network error, not a stale or made-up answer.
    const missing = await page.evaluate(() => fetch('/not-in-the-app.txt').then((r) => `status ${r.status}`, (e) => e.name));
    assert.equal(missing, 'TypeError');
  } finally {
    await context.setOffline(false);
  }
  assert.deepEqual(session.logs.filter((l) => l.startsWith('pageerror')), []);
});
