// SPDX-License-Identifier: MIT
// DOM of the planar method's report, which every result shows: the general figures and the
// warnings (from planar-data.js), and the legend of the tool-path colours (feature colours, and
// the iso-planar NL curves' two alternating colours, listed only while curves are drawn). No
// application state: the method's registry entry (planar.js) calls these.
import { rgbCss } from '../colors.js';
import { fillFigureList, noteItem } from '../panel-dom.js';
import { FEATURES, featureCss } from '../preview.js';
import { CURVE_COLORS } from './isoplanar-data.js';
import { reportRows, warningNotes } from './planar-data.js';

/** The report's general figures as dt/dd pairs (dd data-testid report-<key>); dashes without one. */
export function fillReportFigures(dl, report) {
  fillFigureList(dl, reportRows(report), 'report');
}

/** The report's warnings as list items (class warning, data-code). */
export function fillWarnings(ul, report) {
  ul.replaceChildren(...warningNotes(report).map((w) => noteItem('warning', w.text, w.code)));
}

/** The legend: a swatch per feature, then the NL-curve colours (items data-testid legend-curves, hidden). */
export function fillLegend(ul) {
  ul.replaceChildren();
  for (const f of FEATURES) {
    const li = document.createElement('li');
    const sw = document.createElement('span');
    sw.className = 'swatch';
    sw.style.background = featureCss(f.code);
    li.append(sw, f.name);
    ul.append(li);
  }
  CURVE_COLORS.forEach((color, k) => {
    const li = document.createElement('li');
    li.dataset.testid = 'legend-curves';
    li.hidden = true;
    const sw = document.createElement('span');
    sw.className = 'swatch';
    sw.style.background = rgbCss(color);
    li.append(sw, k === 0 ? 'NL curves 1, 3, …' : 'NL curves 2, 4, …');
    ul.append(li);
  });
}
