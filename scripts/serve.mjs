// SPDX-License-Identifier: MIT
// Zero-dependency static server for the Omnislice page.
//
// Routes (longest prefix first):  /workers/ -> workers/   /wasm/ -> build/wasm/
//                                 /vendor/three/ -> node_modules/three/   / -> web/
// Only GET and HEAD. Paths that escape their folder (.., encoded slashes, NUL, symlinks pointing
// outside) are refused with 403; anything not found is 404. Nothing is ever served from ../shared.
// Every response carries a Content-Security-Policy (contentSecurityPolicy below): scripts, styles,
// workers, wasm and data only from this origin, no inline script but the page's import map (by its
// hash), no eval (WebAssembly compiles under 'wasm-unsafe-eval'), no plugins.
//
// The iframe API (web/embed.html) serves the origins in /embed-origins.json ({"origins": [...]}):
// the list OMNISLICE_EMBED_ORIGINS (comma-separated origins) or startServer's embedOrigins gives,
// answered by this server; without either, the file web/embed-origins.json if the host made one
// (none: no origin may use the iframe).
//
// CLI:  node scripts/serve.mjs            (PORT env, default 8080; HOST env, default 127.0.0.1)
// API:  const { url, close } = await startServer({ port: 0, root });
import crypto from 'node:crypto';
import http from 'node:http';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const REPO_ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');

/** MIME types by lower-case extension; everything else is application/octet-stream. */
export const MIME_TYPES = {
  '.html': 'text/html; charset=utf-8',
  '.js': 'text/javascript; charset=utf-8',
  '.mjs': 'text/javascript; charset=utf-8',
  '.css': 'text/css; charset=utf-8',
  '.json': 'application/json; charset=utf-8',
  '.map': 'application/json; charset=utf-8',
  '.wasm': 'application/wasm',
  '.svg': 'image/svg+xml',
  '.png': 'image/png',
  '.ico': 'image/x-icon',
  '.txt': 'text/plain; charset=utf-8',
  '.md': 'text/plain; charset=utf-8',
  '.gcode': 'text/plain; charset=utf-8',
  '.webmanifest': 'application/manifest+json',
};

/** Route table: URL prefix -> folder relative to the repository root. */
export const ROUTES = [
  ['/workers/', 'workers'],
  ['/wasm/', path.join('build', 'wasm')],
  ['/vendor/three/', path.join('node_modules', 'three')],
  ['/', 'web'],
];

/** MIME type of a file name (application/octet-stream when unknown, e.g. .stl, .obj, .3mf). */
export function mimeType(fileName) {
  return MIME_TYPES[path.extname(fileName).toLowerCase()] || 'application/octet-stream';
}

/**
 * Map a request path to a file path under root, or return {status} when refused.
 * @param {string} urlPath  the request's path (no query), still percent-encoded
 * @param {string} root     repository root
 * @returns {{file: string} | {status: number}}
 */
export function resolveRequestPath(urlPath, root, routes = ROUTES) {
  let decoded;
  try {
    decoded = decodeURIComponent(urlPath);
  } catch {
    return { status: 400 };
  }
  if (decoded.includes('\0') || decoded.includes('\\') || !decoded.startsWith('/')) return { status: 403 };
  // Encoded slashes would let "..%2f" through a segment check; refuse them outright.
  if (/%2f|%5c/i.test(urlPath)) return { status: 403 };
  const segments = decoded.split('/');
  if (segments.some((s) => s === '..' || s === '.')) return { status: 403 };
  // Hidden files (.git, .env, ...) are never served.
  if (segments.some((s) => s.startsWith('.'))) return { status: 404 };
  const route = routes.find(([prefix]) => decoded.startsWith(prefix));
  if (!route) return { status: 404 };
  const base = path.resolve(root, route[1]);
  const rest = decoded.slice(route[0].length);
  const file = path.resolve(base, rest);
  if (file !== base && !file.startsWith(base + path.sep)) return { status: 403 };
  return { file, base };
}

/**
 * The hashes ('sha256-...') of the inline <script> elements of an HTML text: the page's only inline
 * script is its import map (an import map cannot be an external file in Chromium), allowed by its
 * hash, so a script injected into the page does not run.
 */
export function inlineScriptHashes(html) {
  const hashes = [];
  for (const m of html.matchAll(/<script\b([^>]*)>([\s\S]*?)<\/script>/gi)) {
    if (/\bsrc\s*=/.test(m[1])) continue;
    hashes.push(`'sha256-${crypto.createHash('sha256').update(m[2], 'utf8').digest('base64')}'`);
  }
  return hashes;
}

/**
 * The policy every response of the app's server carries, for the app page at root/web/index.html.
 * img-src data: and blob: (the page's empty favicon, thumbnails), no frame-ancestors (portals
 * frame the page), object-src none, base-uri none, form-action none.
 */
export function contentSecurityPolicy(root = REPO_ROOT) {
  let hashes = [];
  try {
    hashes = inlineScriptHashes(fs.readFileSync(path.join(root, 'web', 'index.html'), 'utf8'));
  } catch {
    // no page (a server for other files): no inline script at all
  }
  return [
    "default-src 'self'",
    `script-src 'self' 'wasm-unsafe-eval'${hashes.length ? ' ' + hashes.join(' ') : ''}`,
    "style-src 'self'",
    "img-src 'self' data: blob:",
    "connect-src 'self'",
    "worker-src 'self'",
    "object-src 'none'",
    "base-uri 'none'",
    "form-action 'none'",
  ].join('; ');
}

/**
 * The origins of a comma-separated list ("https://portal.example, http://localhost:3000"), each
 * normalised (URL.origin); throws on an entry that is not an http(s) origin.
 */
export function parseEmbedOrigins(text) {
  const out = [];
  for (const entry of String(text).split(',').map((s) => s.trim()).filter(Boolean)) {
    let url;
    try {
      url = new URL(entry);
    } catch {
      throw new Error(`OMNISLICE_EMBED_ORIGINS: "${entry}" is not an origin (scheme://host[:port])`);
    }
    if (!/^https?:$/.test(url.protocol) || url.origin !== entry.replace(/\/$/, '')) {
      throw new Error(`OMNISLICE_EMBED_ORIGINS: "${entry}" is not an http(s) origin (scheme://host[:port], no path)`);
    }
    out.push(url.origin);
  }
  return out;
}

function sendStatus(res, status) {
  const text = http.STATUS_CODES[status] || 'Error';
  res.writeHead(status, { 'Content-Type': 'text/plain; charset=utf-8', 'Content-Length': Buffer.byteLength(text) });
  res.end(text);
}

async function handle(req, res, root, routes, embedOrigins) {
  if (req.method !== 'GET' && req.method !== 'HEAD') {
    res.setHeader('Allow', 'GET, HEAD');
    sendStatus(res, 405);
    return;
  }
  const urlPath = (req.url || '/').split('?')[0].split('#')[0];
  if (urlPath === '/embed-origins.json' && embedOrigins) {
    const body = JSON.stringify({ origins: embedOrigins });
    res.writeHead(200, {
      'Content-Type': MIME_TYPES['.json'],
      'Content-Length': Buffer.byteLength(body),
      'Cache-Control': 'no-store',
      'X-Content-Type-Options': 'nosniff',
    });
    res.end(req.method === 'HEAD' ? undefined : body);
    return;
  }
  const resolved = resolveRequestPath(urlPath, root, routes);
  if (!resolved.file) {
    sendStatus(res, resolved.status);
    return;
  }
  let file = resolved.file;
  let stat;
  try {
    stat = await fs.promises.stat(file);
    if (stat.isDirectory()) {
      file = path.join(file, 'index.html');
      stat = await fs.promises.stat(file);
    }
    // A symlink inside a served folder must not lead outside it.
    const real = await fs.promises.realpath(file);
    const realBase = await fs.promises.realpath(resolved.base);
    if (real !== realBase && !real.startsWith(realBase + path.sep)) {
      sendStatus(res, 403);
      return;
    }
  } catch {
    sendStatus(res, 404);
    return;
  }
  if (!stat.isFile()) {
    sendStatus(res, 404);
    return;
  }
  res.writeHead(200, {
    'Content-Type': mimeType(file),
    'Content-Length': stat.size,
    'Cache-Control': 'no-cache',
    'X-Content-Type-Options': 'nosniff',
  });
  if (req.method === 'HEAD') {
    res.end();
    return;
  }
  const stream = fs.createReadStream(file);
  stream.on('error', () => res.destroy());
  stream.pipe(res);
}

/**
 * Start the server.
 * @param {{port?: number, host?: string, root?: string, quiet?: boolean,
 *          extraRoutes?: Array<[string, string]>, onRequest?: (path: string) => void,
 *          embedOrigins?: string[]}} options
 *   port 0 picks a free port; root defaults to the repository holding this script; extraRoutes
 *   (prefix -> folder, relative to root or absolute) are tried before the app's ROUTES (tests
 *   add /tests/ and another wasm folder); onRequest sees every request path.
 * @returns {Promise<{url: string, port: number, close: () => Promise<void>}>}
 */
export function startServer({
  port = 8080, host = '127.0.0.1', root = REPO_ROOT, quiet = true, extraRoutes = [], onRequest,
  embedOrigins = process.env.OMNISLICE_EMBED_ORIGINS !== undefined
    ? parseEmbedOrigins(process.env.OMNISLICE_EMBED_ORIGINS) : undefined,
} = {}) {
  const routes = [...extraRoutes, ...ROUTES];
  const csp = contentSecurityPolicy(root);
  const server = http.createServer((req, res) => {
    if (onRequest) onRequest((req.url || '/').split('?')[0]);
    res.setHeader('Content-Security-Policy', csp);
    handle(req, res, root, routes, embedOrigins).catch(() => {
      if (!res.headersSent) sendStatus(res, 500);
      else res.destroy();
    });
  });
  const sockets = new Set();
  server.on('connection', (socket) => {
    sockets.add(socket);
    socket.on('close', () => sockets.delete(socket));
  });
  return new Promise((resolve, reject) => {
    server.once('error', reject);
    server.listen(port, host, () => {
      const actual = server.address().port;
      const shownHost = host.includes(':') ? `[${host}]` : host;
      const url = `http://${shownHost}:${actual}/`;
      if (!quiet) console.log(`Omnislice at ${url}`);
      resolve({
        url,
        port: actual,
        close: () =>
          new Promise((done) => {
            for (const socket of sockets) socket.destroy();
            server.close(() => done());
          }),
      });
    });
  });
}

if (process.argv[1] && path.resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  const port = process.env.PORT !== undefined ? Number(process.env.PORT) : 8080;
  if (!Number.isInteger(port) || port < 0 || port > 65535) {
    console.error(`serve: PORT must be an integer in 0..65535, got "${process.env.PORT}"`);
    process.exit(2);
  }
  let embedOrigins;
  try {
    if (process.env.OMNISLICE_EMBED_ORIGINS !== undefined) embedOrigins = parseEmbedOrigins(process.env.OMNISLICE_EMBED_ORIGINS);
  } catch (err) {
    console.error(`serve: ${err.message}`);
    process.exit(2);
  }
  startServer({ port, host: process.env.HOST || '127.0.0.1', quiet: false, embedOrigins }).catch((err) => {
    console.error(`serve: ${err.message}`);
    process.exit(1);
  });
}
