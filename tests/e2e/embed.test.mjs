// SPDX-License-Identifier: MIT
// The iframe API (web/embed.html, embed.js) driven from two other origins in Chromium: the app's
// server allows one (OMNISLICE_EMBED_ORIGINS' list, here its embedOrigins option); a portal page
// there gets `ready`, progress and a G-code program equal to the app's own slice of the same file;
// a portal page on the other origin gets {type: 'error', code: 'origin_not_allowed'} and no
// program. Each portal is a plain page of its own server (another port: another origin).
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import http from 'node:http';
import os from 'node:os';
import path from 'node:path';

import { IN_CI, ROOT } from './page-controls.mjs';
import { CHROMIUM, browserUnavailable } from '../js/browser.mjs';
import { startServer } from '../js/static-server.mjs';
import { parseEmbedOrigins } from '../../scripts/serve.mjs';

const DEMO = fs.readFileSync(path.join(ROOT, 'web', 'models', 'demo-overhang.stl'));
let skipWhy = null;
let app = null;
let portals = [];
let context = null;
let userDataDir = null;

/** A portal page that frames the app's embed.html (holder.url, read when the page is served). */
function portalPage(appUrl) {
  return `<!doctype html><meta charset="utf-8"><title>portal</title><body><script type="module">
const APP = ${JSON.stringify(appUrl)};
window.messages = [];
window.addEventListener('message', (e) => {
  if (e.origin !== APP) return;
  const m = e.data;
  window.messages.push(m.type === 'result'
    ? { ...m, programText: new TextDecoder().decode(m.programBytes), programBytes: undefined } : m);
});
const frame = document.createElement('iframe');
frame.src = APP + '/embed.html';
frame.addEventListener('load', () => { window.frameLoaded = true; });
document.body.append(frame);
window.slice = async (id, settings) => {
  const bytes = await (await fetch('/demo.stl')).arrayBuffer();
  frame.contentWindow.postMessage({ type: 'slice', id, name: 'demo-overhang.stl', bytes, settings }, APP, [bytes]);
};
</script></body>`;
}

/** A portal's own server (another port: another origin): its page and the demo file. */
async function startPortal(holder) {
  const server = http.createServer((req, res) => {
    if (req.url === '/demo.stl') {
      res.writeHead(200, { 'Content-Type': 'application/octet-stream' });
      res.end(DEMO);
    } else {
      res.writeHead(200, { 'Content-Type': 'text/html; charset=utf-8' });
      res.end(portalPage(holder.url));
    }
  });
  await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
  return {
    url: `http://127.0.0.1:${server.address().port}`,
    close: () => new Promise((done) => { server.closeAllConnections(); server.close(() => done()); }),
  };
}

before(async () => {
  skipWhy = await browserUnavailable();
  if (skipWhy) {
    if (IN_CI) throw new Error(`embed e2e prerequisites: ${skipWhy}`);
    return;
  }
  // The portals first (the app needs the allowed origin); they learn the app's URL through holder.
  const holder = { url: '' };
  const allowed = await startPortal(holder);
  const refused = await startPortal(holder);
  app = await startServer({ root: ROOT, embedOrigins: parseEmbedOrigins(`${allowed.url}`) });
  holder.url = app.url;
  portals = [allowed, refused];
  const { chromium } = await import('playwright-core');
  userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'omnislice-embed-'));
  context = await chromium.launchPersistentContext(userDataDir, {
    executablePath: CHROMIUM, headless: true, serviceWorkers: 'block',
    args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  });
});

after(async () => {
  if (context) await context.close();
  for (const p of portals) await p.close();
  if (app) await app.close();
  if (userDataDir) fs.rmSync(userDataDir, { recursive: true, force: true });
});

test('an allowed portal: ready, progress, and the program of the demo', async (t) => {
  if (skipWhy) return t.skip(skipWhy);
  const page = await context.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  await page.goto(`${portals[0].url}/`);
  await page.waitForFunction(() => window.messages.some((m) => m.type === 'ready'), null, { timeout: 60_000 });
  await page.evaluate(() => window.slice(1, { layer_height: 0.3 }));
  await page.waitForFunction(() => window.messages.some((m) => m.id === 1 && (m.type === 'result' || m.type === 'error')),
    null, { timeout: 180_000 });
  const messages = await page.evaluate(() => window.messages);
  const result = messages.find((m) => m.type === 'result');
  assert.ok(result, JSON.stringify(messages.filter((m) => m.type === 'error')));
  assert.ok(messages.some((m) => m.type === 'progress' && m.id === 1), 'progress messages');
  assert.equal(result.fileName, 'demo-overhang.gcode');
  assert.equal(result.programExtension, 'gcode');
  assert.match(result.programText, /^; omnislice /);
  assert.ok(result.programText.includes('; omnislice:setting layer_height = 0.3'));
  assert.equal(result.report.layers, Math.round(result.report.layers));
  assert.ok(result.report.layers > 10);
  // The same request in the framed app twice gives the same program (the header's date aside).
  await page.evaluate(() => window.slice(2, { layer_height: 0.3 }));
  await page.waitForFunction(() => window.messages.some((m) => m.id === 2 && m.type === 'result'), null, { timeout: 180_000 });
  const second = (await page.evaluate(() => window.messages)).find((m) => m.id === 2 && m.type === 'result');
  const body = (text) => text.slice(text.indexOf('\n') + 1);
  assert.equal(body(second.programText), body(result.programText));
  // A malformed request: an error with a code, the frame still answers.
  await page.evaluate(() => document.querySelector('iframe').contentWindow.postMessage({ type: 'slice', id: 3, name: 7 }, '*'));
  await page.waitForFunction(() => window.messages.some((m) => m.id === 3), null, { timeout: 30_000 });
  const bad = (await page.evaluate(() => window.messages)).find((m) => m.id === 3);
  assert.equal(bad.type, 'error');
  assert.equal(bad.code, 'invalid_option');
  assert.deepEqual(errors, []);
  t.diagnostic(`${messages.filter((m) => m.type === 'progress').length} progress messages; ${result.report.layers} layers`);
  await page.close();
});

test('a portal on another origin: origin_not_allowed, no ready, no program', async (t) => {
  if (skipWhy) return t.skip(skipWhy);
  const page = await context.newPage();
  await page.goto(`${portals[1].url}/`);
  await page.waitForFunction(() => window.frameLoaded === true, null, { timeout: 60_000 });
  await page.evaluate(() => window.slice(1, {}));
  await page.waitForFunction(() => window.messages.some((m) => m.id === 1), null, { timeout: 60_000 });
  const messages = await page.evaluate(() => window.messages);
  assert.deepEqual(messages.map((m) => [m.type, m.code]), [['error', 'origin_not_allowed']]);
  assert.match(messages[0].message, /not an origin this Omnislice serves/);
  await page.close();
});

test('OMNISLICE_EMBED_ORIGINS: origins parsed and normalised; paths and other schemes refused', () => {
  assert.deepEqual(parseEmbedOrigins(' https://portal.example , http://localhost:3000/'), ['https://portal.example', 'http://localhost:3000']);
  assert.deepEqual(parseEmbedOrigins(''), []);
  assert.throws(() => parseEmbedOrigins('https://portal.example/app'), /not an http\(s\) origin/);
  assert.throws(() => parseEmbedOrigins('ftp://x.example'), /not an http\(s\) origin/);
  assert.throws(() => parseEmbedOrigins('portal'), /not an origin/);
});
