// SPDX-License-Identifier: MIT
// Shared setup of the browser tests: headless Chromium via playwright-core (flags of
// /work/shared/TOOLCHAIN.md) on the static server with the app's route map.
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { REPO, startServer } from './static-server.mjs';

export const CHROMIUM = process.env.CHROMIUM_PATH || '/usr/bin/chromium';
export const WASM_DIR = process.env.OMNISLICE_WASM_DIR || path.join(REPO, 'build/wasm');

/** Why browser tests cannot run here, or null. Under CI=true the caller must fail instead. */
export async function browserUnavailable() {
  if (!fs.existsSync(path.join(WASM_DIR, 'omnislice.mjs'))) return `no wasm build in ${WASM_DIR} (run scripts/build-wasm.sh)`;
  if (!fs.existsSync(CHROMIUM)) return `no Chromium at ${CHROMIUM}`;
  try {
    await import('playwright-core');
  } catch {
    return 'playwright-core is not installed (npm ci)';
  }
  return null;
}

/**
 * Launch Chromium and the server; open the page at pagePath. Options: root, the served checkout
 * (default this one; its build/wasm unless OMNISLICE_WASM_DIR is set); viewport {width, height};
 * beforeGoto(context, server), awaited before the page loads (e.g. to route or record requests);
 * serviceWorkers 'block' (default: the page registers none) or 'allow'.
 * Returns {page, context, server, logs (console lines and 'pageerror: ...'), close()}.
 */
export async function openPage(pagePath, { root = REPO, viewport, beforeGoto, serviceWorkers = 'block' } = {}) {
  const { chromium } = await import('playwright-core');
  const server = await startServer({ root, wasmDir: process.env.OMNISLICE_WASM_DIR || path.join(root, 'build/wasm') });
  const userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'omnislice-chromium-'));
  const context = await chromium.launchPersistentContext(userDataDir, {
    executablePath: CHROMIUM,
    headless: true,
    args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync'],
    acceptDownloads: true,
    // The app's service worker (web/sw.js) would answer requests from its cache and hide them
    // from context.route; only the offline test allows it.
    serviceWorkers,
    ...(viewport ? { viewport } : {}),
  });
  const page = context.pages()[0] || await context.newPage();
  const logs = [];
  page.on('console', (m) => logs.push(`${m.type()}: ${m.text()}`));
  page.on('pageerror', (e) => logs.push(`pageerror: ${e.message}`));
  if (beforeGoto) await beforeGoto(context, server);
  await page.goto(`${server.url}${pagePath}`);
  return {
    page, context, server, logs,
    async close() {
      await context.close();
      await server.close();
      fs.rmSync(userDataDir, { recursive: true, force: true });
    },
  };
}
