// SPDX-License-Identifier: MIT
// DOM helpers the report panels share (isoplanar, geodesic, multidir and main.js's charts).
const SVG_NS = 'http://www.w3.org/2000/svg';

/** An SVG element with its attributes and optional text. */
export function svgElement(name, attributes, text) {
  const el = document.createElementNS(SVG_NS, name);
  for (const [k, v] of Object.entries(attributes)) el.setAttribute(k, String(v));
  if (text !== undefined) el.textContent = text;
  return el;
}

/** [key, label, text] rows as dt/dd pairs in `dl` (dd data-testid `${prefix}-${key}`). */
export function fillFigureList(dl, rows, prefix) {
  dl.replaceChildren();
  for (const [key, label, text] of rows) {
    const dt = document.createElement('dt');
    dt.textContent = label;
    const dd = document.createElement('dd');
    dd.dataset.testid = `${prefix}-${key}`;
    dd.textContent = text;
    dl.append(dt, dd);
  }
}
