// SPDX-License-Identifier: MIT
// DOM of the geodesic method's report (paper 002), drawn from report.geodesic by the data helpers
// of geodesic-data.js: the figures list, the traversal table (LPT, DPT, A3 side by side: the core
// plans all three on every slice; the program follows the chosen one, and a row's button asks for
// a slice with that sequence) and the overhang chart per layer as SVG (average overhang angle as
// a line, overhang ratio as bars, the 45° line, a mark at the shown layer). The method's settings
// rows are the 'Geodesic' group of web/settings-fields.js. No application state: the method's
// registry entry (geodesic.js) calls these.
import { fillFigureList, svgElement } from '../panel-dom.js';
import { figure } from '../format.js';
import { geodesicSummaryRows, overhangChartGeometry, traversalRows } from './geodesic-data.js';

/** The figures of report.geodesic as dt/dd pairs (dd data-testid geo-<key>); empty without one. */
export function fillGeoFigures(dl, g) {
  fillFigureList(dl, g ? geodesicSummaryRows(g) : [], 'geo');
}

/**
 * The traversal table: one row per traversal of report.geodesic.traversals (data-testid
 * geo-traversal-<name>, class chosen on the program's, data-retractions / data-air-mm /
 * data-collision-free), the best collision-free figures marked, and in each other row a button
 * (data-testid geo-use-<name>) calling onChoose(name) ('lpt' | 'dpt' | 'a3').
 * @returns {number} rows drawn
 */
export function fillTraversalTable(tbody, g, { onChoose, disabled = false } = {}) {
  tbody.replaceChildren();
  const rows = traversalRows(g);
  for (const r of rows) {
    const tr = document.createElement('tr');
    tr.dataset.testid = `geo-traversal-${r.name}`;
    tr.className = r.chosen ? 'chosen' : '';
    tr.dataset.retractions = String(r.retractions);
    tr.dataset.airMm = String(r.airMoveMm);
    tr.dataset.collisionFree = String(r.collisionFree);
    const cell = (text, best) => {
      const td = document.createElement('td');
      td.textContent = text;
      if (best) td.className = 'best';
      return td;
    };
    const name = cell(r.name);
    name.title = { LPT: 'layer priority: layer by layer', DPT: 'depth priority: up each branch', A3: 'Algorithm 3: up a branch while no collision is possible' }[r.name] || '';
    const free = cell(r.collisionFree ? 'yes' : `no${Number.isFinite(r.collidingNodes) ? ` (${figure(r.collidingNodes)})` : ''}`);
    free.className = r.collisionFree ? 'ok' : 'alert';
    if (!r.collisionFree && r.collidingLowerBound > 0) {
      free.title = `${figure(r.collidingNodes)} IGDS collide; no order has fewer than ${figure(r.collidingLowerBound)} (cycles of collisions, e.g. where two growth fronts close a loop)`;
    }
    const action = document.createElement('td');
    if (r.chosen) {
      action.textContent = 'printed';
    } else {
      const b = document.createElement('button');
      b.type = 'button';
      b.className = 'small';
      b.textContent = 'use';
      b.title = `slice again with the ${r.name} sequence`;
      b.dataset.testid = `geo-use-${r.name}`;
      b.disabled = disabled || !onChoose;
      if (onChoose) b.addEventListener('click', () => onChoose(r.name.toLowerCase()));
      action.append(b);
    }
    tr.append(name, cell(figure(r.retractions), r.fewestRetractions),
      cell(Number.isFinite(r.airMoveMm) ? figure(r.airMoveMm) : '—', r.shortestAir), free, action);
    tbody.append(tr);
  }
  return rows.length;
}

/**
 * Draw the overhang chart of report.geodesic into `svg` (viewBox width x height): ratio bars,
 * y ticks in degrees, the threshold line, the average-angle line with a dot per layer, x ticks
 * (layer numbers, 1-based as the sliders show them), and a mark at `layer`. Sets data-layers,
 * data-points, data-bars, data-max (for tests); clears the chart without a report.
 * @returns {{layers: number, points: number, maxValue: number, meanValue: number, over: number} |
 *   {error: string} | null} over: layers whose average angle is above the threshold
 */
export function drawOverhangChart(svg, g, { layer = null, width = 260, height = 120 } = {}) {
  svg.replaceChildren();
  for (const k of ['layers', 'points', 'bars', 'max', 'layer']) delete svg.dataset[k];
  if (!g) return null;
  let c;
  try {
    c = overhangChartGeometry(g, { width, height });
  } catch (err) {
    return { error: err.message };
  }
  const base = c.plot.y + c.plot.height;
  for (const b of c.bars) {
    const rect = svgElement('rect', { class: 'ratio', x: b.x.toFixed(2), y: b.y.toFixed(2), width: Math.max(b.width, 0.5).toFixed(2), height: b.height.toFixed(2) });
    rect.append(svgElement('title', {}, `layer ${b.layer + 1}: overhang ratio ${figure(b.value)}`));
    svg.append(rect);
  }
  for (const t of c.yTicks) {
    svg.append(svgElement('line', { class: 'grid', x1: c.plot.x, y1: t.y.toFixed(2), x2: c.plot.x + c.plot.width, y2: t.y.toFixed(2) }));
    svg.append(svgElement('text', { class: 'tick', x: c.plot.x - 3, y: (t.y + 3).toFixed(2), 'text-anchor': 'end' }, `${t.value}°`));
  }
  const th = svgElement('line', { class: 'threshold', x1: c.plot.x, y1: c.threshold.y.toFixed(2), x2: c.plot.x + c.plot.width, y2: c.threshold.y.toFixed(2) });
  th.append(svgElement('title', {}, `${c.threshold.value}°: beyond it a layer may need support`));
  svg.append(th);
  svg.append(svgElement('line', { class: 'axis', x1: c.plot.x, y1: base, x2: c.plot.x + c.plot.width, y2: base }));
  for (const t of c.xTicks) {
    const anchor = t.x - c.plot.x < 10 ? 'start' : c.plot.x + c.plot.width - t.x < 10 ? 'end' : 'middle';
    svg.append(svgElement('line', { class: 'axis', x1: t.x.toFixed(2), y1: base, x2: t.x.toFixed(2), y2: base + 3 }));
    svg.append(svgElement('text', { class: 'tick', x: t.x.toFixed(2), y: base + 12, 'text-anchor': anchor }, String(t.value + 1)));
  }
  if (c.path) {
    const line = svgElement('path', { class: 'overhang', d: c.path });
    line.append(svgElement('title', {}, `average overhang angle per layer: mean ${figure(c.meanValue)}°, largest ${figure(c.maxValue)}°`));
    svg.append(line);
  }
  for (const p of c.points) {
    const dot = svgElement('circle', { class: p.value > c.threshold.value ? 'dot over' : 'dot', cx: p.x.toFixed(2), cy: p.y.toFixed(2), r: 1.4 });
    dot.append(svgElement('title', {}, `layer ${p.layer + 1}: ${figure(p.value)}°`));
    svg.append(dot);
  }
  const mark = svgElement('line', { class: 'layer-mark', 'data-testid': 'geo-chart-mark', x1: 0, y1: c.plot.y, x2: 0, y2: base });
  mark.style.display = 'none';
  svg.append(mark);
  svg.dataset.layers = String(c.layers);
  svg.dataset.points = String(c.points.length);
  svg.dataset.bars = String(c.bars.length);
  svg.dataset.max = String(c.maxValue);
  svg.geodesicChart = c;
  setChartLayer(svg, layer);
  const over = c.points.filter((p) => p.value > c.threshold.value).length;
  return { layers: c.layers, points: c.points.length, maxValue: c.maxValue, meanValue: c.meanValue, over };
}

/** Move the chart's layer mark to layer l (null or out of range hides it); data-layer follows. */
export function setChartLayer(svg, l) {
  const c = svg.geodesicChart;
  const mark = svg.querySelector('line.layer-mark');
  if (!c || !mark) return;
  const ok = Number.isInteger(l) && l >= 0 && l < c.layers;
  mark.style.display = ok ? '' : 'none';
  if (!ok) {
    delete svg.dataset.layer;
    return;
  }
  const x = c.layerX(l).toFixed(2);
  mark.setAttribute('x1', x);
  mark.setAttribute('x2', x);
  svg.dataset.layer = String(l);
}
