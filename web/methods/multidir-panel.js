// SPDX-License-Identifier: MIT
// DOM of the multi-directional method's report (paper 000), drawn from report.multidir by the
// data helpers of multidir-data.js: the figures (J_G before -> after, search), the parts table
// (print index with its colour, direction, volume, risky area, layers) and the chart of J_G per
// search level as SVG (also drawn live from the search's progress while it runs). The method's
// settings rows are the 'Multi-directional' group of web/settings-fields.js. No application state:
// the method's registry entry (multidir.js) calls these.
import { fillFigureList, svgElement } from '../panel-dom.js';
import { figure } from '../format.js';
import { jgChartGeometry, multidirSummaryRows, partColorCss, partRows } from './multidir-data.js';

/** The figures of report.multidir as dt/dd pairs (dd data-testid md-<key>); empty without one. */
export function fillMultidirFigures(dl, m) {
  fillFigureList(dl, m ? multidirSummaryRows(m) : [], 'md');
}

/**
 * The parts table: one row per part in print order (data-testid md-part-<index>, a colour swatch
 * like the view's). @returns {number} rows drawn
 */
export function fillPartsTable(tbody, m) {
  tbody.replaceChildren();
  const rows = partRows(m);
  for (const r of rows) {
    const tr = document.createElement('tr');
    tr.dataset.testid = `md-part-${r.index}`;
    const cell = (text, title) => {
      const td = document.createElement('td');
      td.textContent = text;
      if (title) td.title = title;
      return td;
    };
    const index = cell('');
    const swatch = document.createElement('span');
    swatch.className = 'swatch';
    swatch.style.background = partColorCss(r.index);
    index.append(swatch, document.createTextNode(` ${r.index + 1}${r.platform ? ' (platform)' : ''}`));
    tr.append(index, cell(r.direction, `tilt ${figure(r.tiltDeg)}° from +Z`), cell(figure(r.volume)),
      cell(figure(r.risky)), cell(figure(r.layers)));
    if (r.risky > 1e-6) tr.classList.add('risky');
    tbody.append(tr);
  }
  return rows.length;
}

/**
 * Draw J_G per search level (report.multidir.search.J_G_per_level) into `svg`: grid and ticks
 * (mm²), the line with a dot per level, the level numbers. Sets data-points and data-max (for
 * tests); clears the chart without a report.
 * @returns {{points: number, maxValue: number, first: number, last: number} | {error: string} | null}
 */
export function drawJgChart(svg, m, options = {}) {
  const values = m && m.search && Array.isArray(m.search.J_G_per_level) ? m.search.J_G_per_level : null;
  return drawJgLevels(svg, values, options);
}

/**
 * Draw J_G per level from a list of values (level 0 first) into `svg`, as drawJgChart does. With
 * `live` (a search still running: multidir-data.js liveJgLevels) the chart is marked data-live
 * and its line titled as the best found so far; null or no values clear the chart.
 * @returns {{points: number, maxValue: number, first: number, last: number} | {error: string} | null}
 */
export function drawJgLevels(svg, values, { width = 260, height = 110, live = false } = {}) {
  svg.replaceChildren();
  for (const k of ['points', 'max', 'live']) delete svg.dataset[k];
  if (!values || (live && values.length === 0)) return null;
  let c;
  try {
    c = jgChartGeometry(values, { width, height });
  } catch (err) {
    return { error: err.message };
  }
  const base = c.plot.y + c.plot.height;
  for (const t of c.yTicks) {
    svg.append(svgElement('line', { class: 'grid', x1: c.plot.x, y1: t.y.toFixed(2), x2: c.plot.x + c.plot.width, y2: t.y.toFixed(2) }));
    svg.append(svgElement('text', { class: 'tick', x: c.plot.x - 3, y: (t.y + 3).toFixed(2), 'text-anchor': 'end' }, figure(t.value)));
  }
  svg.append(svgElement('line', { class: 'axis', x1: c.plot.x, y1: base, x2: c.plot.x + c.plot.width, y2: base }));
  for (const t of c.xTicks) {
    svg.append(svgElement('text', { class: 'tick', x: t.x.toFixed(2), y: base + 12, 'text-anchor': 'middle' }, String(t.value)));
  }
  if (c.path) {
    const line = svgElement('path', { class: 'overhang', d: c.path });
    line.append(svgElement('title', {}, live ? 'J_G (mm²) of the best decomposition found so far with at most this many planes'
      : 'J_G (mm²) of the best beam after each level'));
    svg.append(line);
  }
  for (const p of c.points) {
    const dot = svgElement('circle', { class: 'dot', cx: p.x.toFixed(2), cy: p.y.toFixed(2), r: 2 });
    dot.append(svgElement('title', {}, `level ${p.level}: J_G ${figure(p.value)} mm²`));
    svg.append(dot);
  }
  svg.dataset.points = String(c.points.length);
  svg.dataset.max = String(c.maxValue);
  if (live) svg.dataset.live = 'true';
  return { points: c.points.length, maxValue: c.maxValue, first: values[0], last: values[values.length - 1] };
}
