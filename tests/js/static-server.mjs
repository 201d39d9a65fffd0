// SPDX-License-Identifier: MIT
// A tiny static server for the browser tests, with the app's route map:
//   /workers/ -> workers/, /wasm/ -> build/wasm/ (or wasmDir), /vendor/three/ -> node_modules/three/,
//   /tests/ -> tests/, / -> web/.  No dependencies; listens on a random free port on 127.0.0.1.
import http from 'node:http';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

export const REPO = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');

const TYPES = {
  '.html': 'text/html; charset=utf-8', '.js': 'text/javascript; charset=utf-8',
  '.mjs': 'text/javascript; charset=utf-8', '.wasm': 'application/wasm', '.json': 'application/json',
  '.css': 'text/css', '.stl': 'application/octet-stream', '.map': 'application/json',
};

/** Start the server. Returns {url, close(), requests: string[]} (requests logs every path). */
export async function startServer({ wasmDir = path.join(REPO, 'build/wasm') } = {}) {
  const routes = [
    ['/workers/', path.join(REPO, 'workers')],
    ['/wasm/', wasmDir],
    ['/vendor/three/', path.join(REPO, 'node_modules/three')],
    ['/tests/', path.join(REPO, 'tests')],
    ['/', path.join(REPO, 'web')],
  ];
  const requests = [];
  const server = http.createServer((req, res) => {
    const urlPath = decodeURIComponent(new URL(req.url, 'http://x').pathname);
    requests.push(urlPath);
    const route = routes.find(([prefix]) => urlPath.startsWith(prefix));
    const root = route[1];
    let file = path.join(root, urlPath.slice(route[0].length));
    if (!file.startsWith(root)) { res.writeHead(403).end(); return; }
    if (urlPath.endsWith('/')) file = path.join(file, 'index.html');
    fs.readFile(file, (err, data) => {
      if (err) { res.writeHead(404, { 'content-type': 'text/plain' }).end('not found'); return; }
      res.writeHead(200, {
        'content-type': TYPES[path.extname(file)] || 'application/octet-stream',
        'cache-control': 'no-store',
      });
      res.end(data);
    });
  });
  await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
  const { port } = server.address();
  return {
    url: `http://127.0.0.1:${port}`,
    requests,
    close: () => new Promise((resolve) => { server.closeAllConnections?.(); server.close(resolve); }),
  };
}
