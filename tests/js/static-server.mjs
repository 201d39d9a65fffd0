// SPDX-License-Identifier: MIT
// The browser tests' server: the app's own server (scripts/serve.mjs) on a free port, with two
// extra routes: /tests/ -> tests/ (harness pages) and /wasm/ -> wasmDir (a chosen build).
import path from 'node:path';
import { fileURLToPath } from 'node:url';

import { startServer as startAppServer } from '../../scripts/serve.mjs';

export const REPO = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');

/**
 * Start the server on `root` (default this checkout). Returns {url (no trailing slash), close(),
 * requests: string[]}.
 */
export async function startServer({ root = REPO, wasmDir = path.join(root, 'build/wasm'), embedOrigins } = {}) {
  const requests = [];
  const server = await startAppServer({
    port: 0,
    root,
    extraRoutes: [['/tests/', 'tests'], ['/wasm/', wasmDir]],
    onRequest: (p) => requests.push(decodeURIComponent(p)),
    embedOrigins,
  });
  return { url: server.url.replace(/\/$/, ''), requests, close: server.close };
}
