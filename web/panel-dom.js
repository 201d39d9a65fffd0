// SPDX-License-Identifier: MIT
// DOM helpers the page's panels share: elements by data-testid, SVG elements, figure lists, notes,
// file inputs and file downloads.
const SVG_NS = 'http://www.w3.org/2000/svg';

/** The page's element with data-testid `id` (the tests find elements the same way), or null. */
export function byTestId(id) {
  return document.querySelector(`[data-testid="${id}"]`);
}

/** An SVG element with its attributes and optional text. */
export function svgElement(name, attributes, text) {
  const el = document.createElementNS(SVG_NS, name);
  for (const [k, v] of Object.entries(attributes)) el.setAttribute(k, String(v));
  if (text !== undefined) el.textContent = text;
  return el;
}

/**
 * [key, label, text, state?] rows as dt/dd pairs in `dl` (dd data-testid `${prefix}-${key}`); a
 * row's state (e.g. 'pass', 'fail') becomes the dd's class and data-state.
 */
export function fillFigureList(dl, rows, prefix) {
  dl.replaceChildren();
  for (const [key, label, text, state] of rows) {
    const dt = document.createElement('dt');
    dt.textContent = label;
    const dd = document.createElement('dd');
    dd.dataset.testid = `${prefix}-${key}`;
    dd.textContent = text;
    if (state) {
      dd.className = state;
      dd.dataset.state = state;
    }
    dl.append(dt, dd);
  }
}

/** A list item of a notes list: text, class `kind` (warning, error), data-code when given. */
export function noteItem(kind, text, code) {
  const li = document.createElement('li');
  li.className = kind;
  if (code !== undefined) li.dataset.code = code;
  li.textContent = text;
  return li;
}

/** A range input over n items (0..n-1) set to the last; disabled without items. */
export function setSliderRange(slider, n) {
  slider.max = String(Math.max(n - 1, 0));
  slider.value = slider.max;
  slider.disabled = n === 0;
}

/** Run `load(file)` (async) on a file input's chosen file, then clear the input (the same file may come again). */
export function onFileChosen(input, load) {
  input.addEventListener('change', (e) => {
    const file = e.target.files && e.target.files[0];
    load(file).finally(() => { e.target.value = ''; });
  });
}

/** Offer a Blob as a download named `fileName` (the object URL is revoked after a while). */
export function downloadBlob(blob, fileName) {
  const url = URL.createObjectURL(blob);
  const a = document.createElement('a');
  a.href = url;
  a.download = fileName;
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 30000);
}
