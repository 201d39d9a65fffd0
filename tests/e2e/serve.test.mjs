// SPDX-License-Identifier: MIT
// The static server: route map, MIME types, traversal refusal, 404s, HEAD and method handling.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import net from 'node:net';
import crypto from 'node:crypto';
import { startServer, resolveRequestPath, mimeType, inlineScriptHashes } from '../../scripts/serve.mjs';

// A throw-away root with the four served folders and a secret file next to them.
const root = fs.mkdtempSync(path.join(os.tmpdir(), 'omnislice-serve-'));
const write = (rel, text) => {
  fs.mkdirSync(path.dirname(path.join(root, rel)), { recursive: true });
  fs.writeFileSync(path.join(root, rel), text);
};
// The page's inline import map is allowed by its hash; the external script needs no hash.
const IMPORT_MAP = '\n  {"imports": {"three": "/vendor/three/build/three.module.js"}}\n';
const INDEX = `<!doctype html><title>t</title><script type="importmap">${IMPORT_MAP}</script>` +
  '<script type="module" src="/app.js"></script>';
write('web/index.html', INDEX);
write('web/app.js', 'export const x = 1;');
write('web/styles.css', 'body{}');
write('web/models/part.stl', 'solid x\nendsolid x\n');
write('web/sub/index.html', 'sub index');
write('workers/engine.js', 'export {}');
write('build/wasm/omnislice.mjs', 'export default 1');
write('build/wasm/omnislice.wasm', '\0asm');
write('node_modules/three/build/three.module.js', 'export const REVISION = "x";');
write('secret.txt', 'do not serve');
write('web/.hidden', 'hidden');
fs.symlinkSync(path.join(root, 'secret.txt'), path.join(root, 'web', 'link.txt'));

let server;
before(async () => {
  server = await startServer({ port: 0, root });
});
after(async () => {
  await server.close();
  fs.rmSync(root, { recursive: true, force: true });
});

// Raw request (no URL normalisation by a client), returns {status, headers, body}.
function raw(requestPath, method = 'GET') {
  return new Promise((resolve, reject) => {
    const socket = net.connect(server.port, '127.0.0.1', () => {
      socket.write(`${method} ${requestPath} HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n`);
    });
    let data = '';
    socket.on('data', (d) => { data += d.toString('latin1'); });
    socket.on('end', () => {
      const [head, ...rest] = data.split('\r\n\r\n');
      const lines = head.split('\r\n');
      const status = Number(lines[0].split(' ')[1]);
      const headers = Object.fromEntries(lines.slice(1).map((l) => {
        const i = l.indexOf(':');
        return [l.slice(0, i).toLowerCase(), l.slice(i + 1).trim()];
      }));
      resolve({ status, headers, body: rest.join('\r\n\r\n') });
    });
    socket.on('error', reject);
  });
}

test('startServer on port 0 reports a loopback URL with the chosen port', () => {
  assert.match(server.url, /^http:\/\/127\.0\.0\.1:\d+\/$/);
  assert.ok(server.port > 0);
  assert.equal(new URL(server.url).port, String(server.port));
});

test('routes map to their folders with the right MIME types', async () => {
  const cases = [
    ['/', 'text/html', INDEX],
    ['/app.js', 'text/javascript', 'export const x = 1;'],
    ['/styles.css', 'text/css', 'body{}'],
    ['/models/part.stl', 'application/octet-stream', 'solid x\nendsolid x\n'],
    ['/sub/', 'text/html', 'sub index'],
    ['/workers/engine.js', 'text/javascript', 'export {}'],
    ['/wasm/omnislice.mjs', 'text/javascript', 'export default 1'],
    ['/wasm/omnislice.wasm', 'application/wasm', '\0asm'],
    ['/vendor/three/build/three.module.js', 'text/javascript', 'export const REVISION = "x";'],
    ['/app.js?v=3', 'text/javascript', 'export const x = 1;'],
  ];
  for (const [p, type, body] of cases) {
    const r = await raw(p);
    assert.equal(r.status, 200, p);
    assert.ok(r.headers['content-type'].startsWith(type), `${p}: ${r.headers['content-type']}`);
    assert.equal(r.body, body, p);
    assert.equal(Number(r.headers['content-length']), Buffer.byteLength(body, 'latin1'), p);
  }
});

test('path traversal, encoded separators, hidden files and escaping symlinks are refused', async () => {
  for (const p of ['/../secret.txt', '/%2e%2e/secret.txt', '/models/..%2f..%2fsecret.txt', '/workers/../secret.txt',
    '/vendor/three/../../secret.txt', '/%2e%2e%5csecret.txt', '/a%00b', '/%E0%A4%A']) {
    const r = await raw(p);
    assert.ok(r.status === 403 || r.status === 400, `${p} gave ${r.status}`);
    assert.ok(!r.body.includes('do not serve'), p);
  }
  assert.equal((await raw('/.hidden')).status, 404);
  assert.equal((await raw('/link.txt')).status, 403);
});

test('unknown paths give 404, other methods 405, HEAD has headers and no body', async () => {
  assert.equal((await raw('/nope.js')).status, 404);
  assert.equal((await raw('/wasm/missing.wasm')).status, 404);
  assert.equal((await raw('/workers/')).status, 404);
  const post = await raw('/', 'POST');
  assert.equal(post.status, 405);
  assert.equal(post.headers.allow, 'GET, HEAD');
  const head = await raw('/app.js', 'HEAD');
  assert.equal(head.status, 200);
  assert.equal(head.body, '');
  assert.equal(head.headers['content-length'], '19');
});

test('every response carries the Content-Security-Policy; inline scripts only by the page\'s hashes', async () => {
  const hash = `'sha256-${crypto.createHash('sha256').update(IMPORT_MAP).digest('base64')}'`;
  for (const [p, status] of [['/', 200], ['/app.js', 200], ['/wasm/omnislice.wasm', 200], ['/missing', 404],
    ['/..%2fsecret.txt', 403]]) {
    const r = await raw(p);
    assert.equal(r.status, status, p);
    const csp = r.headers['content-security-policy'];
    assert.ok(csp, `${p}: no policy`);
    const directives = Object.fromEntries(csp.split(';').map((d) => d.trim().split(/\s+/)).map(([k, ...v]) => [k, v]));
    assert.deepEqual(directives['default-src'], ["'self'"]);
    assert.deepEqual(directives['script-src'], ["'self'", "'wasm-unsafe-eval'", hash], p);
    assert.deepEqual(directives['style-src'], ["'self'"]);
    assert.deepEqual(directives['object-src'], ["'none'"]);
    assert.ok(!/unsafe-inline|'unsafe-eval'|\*/.test(csp), csp);
  }
  // The hashes are the inline scripts' own (another text, another hash); src scripts have none.
  assert.deepEqual(inlineScriptHashes('<script src="/a.js"></script><p>x</p>'), []);
  const two = inlineScriptHashes('<SCRIPT type="importmap">a</SCRIPT><script>b</script>');
  assert.equal(two.length, 2);
  assert.notEqual(two[0], two[1]);
  assert.equal(two[0], `'sha256-${crypto.createHash('sha256').update('a').digest('base64')}'`);
});

test('resolveRequestPath and mimeType agree with the route table', () => {
  const r = resolveRequestPath('/wasm/omnislice.wasm', '/repo');
  assert.equal(r.file, path.join('/repo', 'build', 'wasm', 'omnislice.wasm'));
  assert.equal(resolveRequestPath('/x/../../etc/passwd', '/repo').status, 403);
  assert.equal(mimeType('a.MJS'), 'text/javascript; charset=utf-8');
  assert.equal(mimeType('model.3mf'), 'application/octet-stream');
  assert.equal(mimeType('model.obj'), 'application/octet-stream');
});

test('the CLI honours PORT and prints the URL', async () => {
  const { spawn } = await import('node:child_process');
  const script = path.resolve(path.dirname(new URL(import.meta.url).pathname), '../../scripts/serve.mjs');
  const child = spawn(process.execPath, [script], { env: { ...process.env, PORT: '0' } });
  try {
    const line = await new Promise((resolve, reject) => {
      child.stdout.once('data', (d) => resolve(d.toString()));
      child.once('exit', (code) => reject(new Error(`serve exited with ${code}`)));
    });
    const m = line.match(/http:\/\/127\.0\.0\.1:(\d+)\//);
    assert.ok(m, line);
    const res = await fetch(`http://127.0.0.1:${m[1]}/index.html`);
    assert.equal(res.status, 200);
    assert.match(await res.text(), /Omnislice/);
  } finally {
    child.kill();
  }
});
