// SPDX-License-Identifier: MIT
// DOM of the iso-planar report (paper 003), drawn from report.isoplanar by the data helpers of
// isoplanar-data.js: the polar plot of v_e(theta) as SVG (rings, axes, the closed curve, theta*
// and a compared direction marked), the figures list and the comparison table of two runs with
// the benchmark means. No application state: the surface
// method's registry entry (surface.js) owns the runs and calls these.
import { fillFigureList, svgElement } from '../panel-dom.js';
import { figure, formatSeconds, percentText } from '../format.js';
import { comparisonRows, isoplanarSummaryRows, polarPlotGeometry, thetaFromPlotPoint } from './isoplanar-data.js';

/**
 * Draw the polar plot of iso.curve into `svg` (its viewBox is size x size): rings with their
 * values, the 0° and 90° axes, the curve closed over 0..360, theta* as a solid line through the
 * centre with dots on the curve, `compareTheta` (degrees, or null) dashed, `candidateTheta` (a
 * direction chosen for the next comparison, or null) dotted. Sets data-samples, data-theta-star,
 * data-compare-theta and data-candidate-theta (for tests); clears the plot without a curve.
 * @returns {{theta: number, value: number} | {error: string} | null} theta* and v_e there; null
 *   without a curve
 */
export function drawPolarPlot(svg, iso, { compareTheta = null, candidateTheta = null, size = 220 } = {}) {
  svg.replaceChildren();
  for (const k of ['samples', 'thetaStar', 'compareTheta', 'candidateTheta']) delete svg.dataset[k];
  if (!iso || !Array.isArray(iso.curve)) return null;
  let g;
  try {
    g = polarPlotGeometry(iso.curve, {
      size, thetaStar: iso.theta_deg, valueStar: iso.deposition_rate_mm3_s,
      extra: [compareTheta === null ? NaN : compareTheta, candidateTheta === null ? NaN : candidateTheta],
    });
  } catch (err) {
    return { error: err.message };
  }
  for (const ring of g.rings) {
    svg.append(svgElement('circle', { class: 'ring', cx: g.cx, cy: g.cy, r: ring.r.toFixed(2) }));
    svg.append(svgElement('text', { class: 'ring-label', x: g.cx + 2, y: (g.cy - ring.r - 1).toFixed(2) }, figure(ring.value)));
  }
  const outer = g.rings.length ? g.rings[g.rings.length - 1].r : g.radius;
  svg.append(svgElement('line', { class: 'axis', x1: g.cx - outer, y1: g.cy, x2: g.cx + outer, y2: g.cy }));
  svg.append(svgElement('line', { class: 'axis', x1: g.cx, y1: g.cy - outer, x2: g.cx, y2: g.cy + outer }));
  svg.append(svgElement('text', { class: 'label', x: g.cx + outer + 2, y: g.cy - 2 }, '0°'));
  svg.append(svgElement('text', { class: 'label', x: g.cx - 3, y: g.cy - outer + 8, 'text-anchor': 'end' }, '90°'));
  const curve = svgElement('path', { class: 'curve', d: g.path });
  curve.append(svgElement('title', {}, `v_e(θ), ${g.samples} directions, sampled max ${figure(g.vMax)} mm³/s at ${figure(g.best.theta)}°`));
  svg.append(curve);
  const drawMark = (m, cls, testid, title) => {
    const line = svgElement('line', {
      class: cls, 'data-testid': testid, x1: m.line[0][0].toFixed(2), y1: m.line[0][1].toFixed(2), x2: m.line[1][0].toFixed(2), y2: m.line[1][1].toFixed(2),
    });
    line.append(svgElement('title', {}, title));
    svg.append(line);
    for (const d of m.dots) svg.append(svgElement('circle', { class: `${cls}-dot`, cx: d[0].toFixed(2), cy: d[1].toFixed(2), r: 3 }));
  };
  // extra keeps only the finite directions: tell the compared one from the candidate by value.
  const compareMark = compareTheta === null ? null : g.marks[0];
  const candidateMark = candidateTheta === null ? null : g.marks[compareMark ? 1 : 0];
  if (compareMark) drawMark(compareMark, 'compare', 'iso-compare-mark', `compared θ = ${figure(compareMark.theta)}°: v_e ≈ ${figure(compareMark.value)} mm³/s`);
  if (candidateMark) drawMark(candidateMark, 'candidate', 'iso-candidate-mark', `θ = ${figure(candidateMark.theta)}°: v_e ≈ ${figure(candidateMark.value)} mm³/s`);
  drawMark(g.star, 'star', 'iso-star-mark', `θ* = ${figure(g.star.theta)}°: v_e = ${figure(g.star.value)} mm³/s`);
  svg.dataset.samples = String(g.samples);
  svg.dataset.thetaStar = String(g.star.theta);
  if (compareMark) svg.dataset.compareTheta = String(compareMark.theta);
  if (candidateMark) svg.dataset.candidateTheta = String(candidateMark.theta);
  return { theta: g.star.theta, value: g.star.value };
}

/** The drive-plane direction (degrees in [0, 180)) under a pointer event on the plot, or null. */
export function plotThetaAt(svg, clientX, clientY) {
  const box = svg.getBoundingClientRect();
  if (!box.width || !box.height) return null;
  const view = svg.viewBox.baseVal;
  const x = ((clientX - box.left) / box.width) * view.width;
  const y = ((clientY - box.top) / box.height) * view.height;
  return thetaFromPlotPoint(x, y, view.width / 2, view.height / 2);
}

/** The figures of report.isoplanar as dt/dd pairs (dd data-testid iso-<key>); empty without one. */
export function fillIsoFigures(dl, iso) {
  fillFigureList(dl, iso ? isoplanarSummaryRows(iso) : [], 'iso');
}

/**
 * The comparison table's rows (comparisonRows of `runs`): run, theta, time, path, v_e, with the
 * later rows' time and path relative to the first run. Rows carry data-testid iso-compare-<key>,
 * class run | benchmark, and data-time / data-path / data-rate.
 */
export function fillCompareTable(tbody, runs) {
  tbody.replaceChildren();
  for (const row of comparisonRows(runs)) {
    const tr = document.createElement('tr');
    tr.className = row.key === 'benchmark' ? 'benchmark' : 'run';
    tr.dataset.testid = `iso-compare-${row.key}`;
    const cell = (text, delta) => {
      const td = document.createElement('td');
      td.textContent = text;
      if (delta) {
        const span = document.createElement('span');
        span.className = 'delta';
        span.textContent = ` (${delta})`;
        td.append(span);
      }
      return td;
    };
    const first = row.key === 'run0';
    tr.append(
      cell(row.label),
      cell(Number.isFinite(row.theta) ? `${figure(row.theta)}°` : '—'),
      cell(formatSeconds(row.time), first ? '' : percentText(row.timeDelta)),
      cell(Number.isFinite(row.path) ? `${figure(row.path)} mm` : '—', first ? '' : percentText(row.pathDelta)),
      cell(figure(row.rate)),
    );
    tr.dataset.time = String(row.time);
    tr.dataset.path = String(row.path);
    tr.dataset.rate = String(row.rate);
    tbody.append(tr);
  }
}
