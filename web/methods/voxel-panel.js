// SPDX-License-Identifier: MIT
// DOM of the voxel method's report (paper 001), drawn from report.voxel by the data helpers of
// voxel-data.js: the figures list and the layer-thickness histogram as SVG (bars, ticks in mm, the
// mean and ± one standard deviation marked). No application state: the method's registry entry
// (voxel.js) calls these.
import { formatMm, withUnit } from '../format.js';
import { fillFigureList, svgElement } from '../panel-dom.js';
import { histogramGeometry, voxelSummaryRows } from './voxel-data.js';

/** The figures of report.voxel as dt/dd pairs (dd data-testid voxel-<key>); empty without one. */
export function fillVoxelFigures(dl, v) {
  fillFigureList(dl, v ? voxelSummaryRows(v) : [], 'voxel');
}

/**
 * Draw report.voxel.thickness.histogram (counts of thickness minus the mean, mm) into `svg`:
 * bars, x ticks in mm, a line at deviation 0 (the mean) and dotted lines at ± one std; the
 * statistics line goes to `stats`. Sets data-bars and data-total (for tests); clears the chart
 * without a histogram.
 */
export function drawThicknessHistogram(svg, stats, thickness) {
  svg.replaceChildren();
  delete svg.dataset.bars;
  delete svg.dataset.total;
  const hist = thickness && thickness.histogram;
  if (!hist) {
    stats.textContent = '—';
    return;
  }
  let geo;
  try {
    geo = histogramGeometry(hist, { width: 260, height: 110 });
  } catch (err) {
    stats.textContent = `(${err.message})`;
    return;
  }
  for (const b of geo.bars) {
    const rect = svgElement('rect', {
      class: b.count > 0 ? 'bar' : 'bar empty', x: b.x + 0.5, y: b.count > 0 ? b.y : geo.plot.y + geo.plot.height - 1,
      width: Math.max(b.width - 1, 0.5), height: b.count > 0 ? b.height : 1,
    });
    rect.append(svgElement('title', {}, `${formatMm(b.from)}–${formatMm(b.to)} mm: ${b.count}`));
    svg.append(rect);
  }
  const base = geo.plot.y + geo.plot.height;
  svg.append(svgElement('line', { class: 'axis', x1: geo.plot.x, y1: base, x2: geo.plot.x + geo.plot.width, y2: base }));
  // Labels near the ends are anchored inside the plot so they are not clipped.
  for (const t of geo.ticks) {
    const anchor = t.x - geo.plot.x < 14 ? 'start' : geo.plot.x + geo.plot.width - t.x < 14 ? 'end' : 'middle';
    svg.append(svgElement('line', { class: 'axis', x1: t.x, y1: base, x2: t.x, y2: base + 3 }));
    svg.append(svgElement('text', { class: 'tick', x: t.x, y: base + 12, 'text-anchor': anchor }, t.label));
  }
  const n = geo.bars.length;
  const std = Number(thickness.std_mm);
  if (n) {
    const lo = geo.bars[0].from;
    const hi = geo.bars[n - 1].to;
    const marks = [[0, 'mean']];
    if (std > 0) marks.push([-std, 'std'], [std, 'std']);
    for (const [d, cls] of marks) {
      if (d < lo || d > hi) continue;
      const x = geo.plot.x + ((d - lo) / (hi - lo)) * geo.plot.width;
      svg.append(svgElement('line', { class: cls, x1: x, y1: geo.plot.y, x2: x, y2: base }));
    }
  }
  svg.dataset.bars = String(n);
  svg.dataset.total = String(geo.total);
  const mm = (x) => withUnit(Number(x), 'mm', formatMm);
  stats.textContent = `mean ${mm(thickness.mean_mm)}, std ${mm(thickness.std_mm)}, max deviation ${mm(thickness.max_deviation_mm)}`
    + (Number.isFinite(thickness.samples) ? ` (${thickness.samples.toLocaleString('en')} samples)` : '');
}
