// SPDX-License-Identifier: MIT
// Controls of the app page the method e2e tests share: settings by data-testid, range sliders,
// the slice counter and waiting for a slice. `getPage` returns the Playwright page (opened later,
// in the test file's `before`).
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
