// SPDX-License-Identifier: MIT
// Controls of the app page the method e2e tests share: settings by data-testid, range sliders,
// the slice counter and waiting for a slice. `getPage` returns the Playwright page (opened later,
// in the test file's `before`).
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { browserUnavailable, openPage } from '../js/browser.mjs';

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
const tid = (id) => `[data-testid="${id}"]`;

export function pageControls(getPage) {
  /** Set a setting's input (select, checkbox or text/number) and fire its change. */
  async function setSetting(testid, value) {
    const input = getPage().locator(tid(testid));
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
    await getPage().locator(tid(testid)).evaluate((el, v) => {
      el.value = String(v);
      el.dispatchEvent(new Event('input', { bubbles: true }));
    }, value);
  }
  const sliceCount = () => getPage().evaluate(() => Number(document.body.dataset.sliceCount || 0));
  /** Wait for the slice after `before` slices to finish (or fail: the error text is returned). */
  async function waitSliced(before, timeout = 300_000) {
    const page = getPage();
    await page.waitForFunction((n) => (document.body.dataset.state === 'done' && Number(document.body.dataset.sliceCount) > n)
      || document.body.dataset.state === 'error', before, { timeout });
    if (await page.evaluate(() => document.body.dataset.state) === 'error') return page.textContent(tid('error-message'));
    return null;
  }
  return { setSetting, slide, sliceCount, waitSliced };
}

/**
 * The app page of a method e2e test, opened in `before`: null skipWhy and an open session once
 * the page has sliced its demo (the planar slice on load), a temporary folder for downloads, and
 * build/e2e for screenshots. Without a browser: skipWhy says why (an error under CI=true).
 * @returns {Promise<{skipWhy: string|null, session?: object, page?: object, tmpDir?: string}>}
 */
export async function openAppPage(label, { height = 900 } = {}) {
  const skipWhy = await browserUnavailable();
  if (skipWhy) {
    if (process.env.CI === 'true') throw new Error(`${label} e2e prerequisites: ${skipWhy}`);
    return { skipWhy };
  }
  fs.mkdirSync(path.join(ROOT, 'build', 'e2e'), { recursive: true });
  const tmpDir = fs.mkdtempSync(path.join(os.tmpdir(), `omnislice-${label}-e2e-`));
  const session = await openPage('/');
  const page = session.page;
  await page.setViewportSize({ width: 1280, height });
  await page.waitForFunction(() => document.body.dataset.state === 'done' && Number(document.body.dataset.sliceCount) >= 1, null, { timeout: 180_000 });
  return { skipWhy: null, session, page, tmpDir };
}

/** Close what openAppPage opened (either may be missing). */
export async function closeAppPage({ session, tmpDir }) {
  if (session) await session.close();
  if (tmpDir) fs.rmSync(tmpDir, { recursive: true, force: true });
}
