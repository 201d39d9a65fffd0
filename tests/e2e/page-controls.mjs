// SPDX-License-Identifier: MIT
// The app page of an end-to-end test file, set up in one place. appPage(label) registers the
// file's `before` and `after` hooks: the server and headless Chromium (../js/browser.mjs), the page
// opened (by default at /?demo=overhang: the planar overhang piece on cartesian3, which these
// files start from; first-visit.test.mjs opens / as a new user does) and, by default, its demo's
// first slice awaited; a temporary folder for downloads;
// everything closed afterwards. It returns the page and the controls the tests share: settings by
// data-testid, range sliders, the slice counter, waiting for a state or a slice, downloading the
// program. Screenshots go to OUT_DIR (build/e2e).
import { after, before } from 'node:test';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { browserUnavailable, openPage } from '../js/browser.mjs';

export const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
export const OUT_DIR = path.join(ROOT, 'build', 'e2e');
export const IN_CI = process.env.CI === 'true';
/** The CSS selector of data-testid `id`. */
export const tid = (id) => `[data-testid="${id}"]`;

const SLICE_TIMEOUT = 180_000;

/** Why the page cannot be served from `root` here (its engine, wasm build, three.js), or null. */
async function pageUnavailable(root) {
  const needed = [
    [path.join(root, 'workers', 'engine.js'), 'workers/engine.js'],
    ...(process.env.OMNISLICE_WASM_DIR ? [] : [[path.join(root, 'build', 'wasm', 'omnislice.mjs'), 'build/wasm/omnislice.mjs (bash scripts/build-wasm.sh)']]),
    [path.join(root, 'node_modules', 'three', 'build', 'three.module.js'), 'node_modules/three (npm ci)'],
  ];
  const missing = needed.filter(([p]) => !fs.existsSync(p)).map(([, what]) => what);
  return missing.length ? `missing: ${missing.join(', ')}` : browserUnavailable();
}

/**
 * The app page of this test file (see the file comment). Options: height of the 1280-wide
 * viewport; required: a missing prerequisite fails the file (otherwise the tests skip, except
 * under CI=true); root: the served checkout; path: the page's address (default /?demo=overhang);
 * waitForDemo: wait in `before` for the demo's slice on load; beforeGoto(context, server): run
 * before the page loads.
 * @returns {{page, skip, tmpDir, server, context, pageErrors, setSetting, slide, sliceCount, waitState,
 *   waitSliced, sliceAndWait, downloadProgram}} page: the Playwright page, usable at module level (it forwards to
 *   the page opened in `before`); skip(t): true (the test skipped with the reason) when the page
 *   could not open
 */
export function appPage(label, { height = 900, required = false, root = ROOT, path: pagePath = '/?demo=overhang', waitForDemo = true, beforeGoto } = {}) {
  let session = null;
  let tmpDir = null;
  let skipWhy = null;
  const current = () => {
    if (!session) throw new Error(`${label} e2e: the page is not open (${skipWhy || 'used before the before hook'})`);
    return session.page;
  };
  const page = new Proxy({}, {
    get(_, key) {
      const p = current();
      const value = p[key];
      return typeof value === 'function' ? value.bind(p) : value;
    },
  });

  /** Wait until the page reaches `state` with data-slice-count >= minSlices (when given). */
  async function waitState(state, { minSlices, timeout = SLICE_TIMEOUT } = {}) {
    await page.waitForFunction(
      ([s, n]) => document.body.dataset.state === s && (n === null || Number(document.body.dataset.sliceCount || 0) >= n),
      [state, minSlices ?? null],
      { timeout },
    );
  }
  /** Set a setting's input (select, checkbox or text/number) and fire its change. */
  async function setSetting(testid, value) {
    const input = page.locator(tid(testid));
    const tag = await input.evaluate((el) => el.tagName);
    if (tag === 'SELECT') await input.selectOption(String(value));
    else if ((await input.getAttribute('type')) === 'checkbox') await input.setChecked(!!value);
    else {
      await input.fill(String(value));
      await input.dispatchEvent('change');
    }
  }
  /** Set a range input's value and fire `input` (as a drag does). */
  async function slide(testid, value) {
    await page.locator(tid(testid)).evaluate((el, v) => {
      el.value = String(v);
      el.dispatchEvent(new Event('input', { bubbles: true }));
    }, value);
  }
  const sliceCount = () => page.evaluate(() => Number(document.body.dataset.sliceCount || 0));
  /** Wait for the slice after `before` slices to finish (or fail: the error text is returned). */
  async function waitSliced(before, timeout = 300_000) {
    await page.waitForFunction((n) => (document.body.dataset.state === 'done' && Number(document.body.dataset.sliceCount) > n)
      || document.body.dataset.state === 'error', before, { timeout });
    if (await page.evaluate(() => document.body.dataset.state) === 'error') return page.textContent(tid('error-message'));
    return null;
  }
  /**
   * Click Slice (waiting up to two minutes for it to be enabled) and wait for the slice: null when
   * it is done, else the error text.
   */
  async function sliceAndWait(timeout = 300_000) {
    const before = await sliceCount();
    await page.click(tid('slice-button'), { timeout: 120_000 });
    return waitSliced(before, timeout);
  }
  /** Click the download button; the program file's name and text. */
  async function downloadProgram() {
    const [download] = await Promise.all([page.waitForEvent('download'), page.click(tid('download-program'))]);
    const file = path.join(tmpDir, `dl-${Date.now()}-${download.suggestedFilename()}`);
    await download.saveAs(file);
    return { name: download.suggestedFilename(), text: fs.readFileSync(file, 'utf8') };
  }

  before(async () => {
    skipWhy = await pageUnavailable(root);
    if (skipWhy) {
      if (required || IN_CI) throw new Error(`${label} e2e prerequisites: ${skipWhy}`);
      return;
    }
    fs.mkdirSync(OUT_DIR, { recursive: true });
    tmpDir = fs.mkdtempSync(path.join(os.tmpdir(), `omnislice-${label}-e2e-`));
    session = await openPage(pagePath, { root, viewport: { width: 1280, height }, beforeGoto });
    if (waitForDemo) await waitState('done', { minSlices: 1 });
  });

  after(async () => {
    if (session) await session.close();
    if (tmpDir) fs.rmSync(tmpDir, { recursive: true, force: true });
  });

  return {
    page,
    skip(t) {
      if (!skipWhy) return false;
      t.skip(skipWhy);
      return true;
    },
    get tmpDir() { return tmpDir; },
    get server() { return session && session.server; },
    get context() { return session && session.context; },
    /** The page's uncaught errors so far. */
    pageErrors: () => (session ? session.logs.filter((l) => l.startsWith('pageerror')) : []),
    setSetting, slide, sliceCount, waitState, waitSliced, sliceAndWait, downloadProgram,
  };
}
