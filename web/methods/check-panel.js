// SPDX-License-Identifier: MIT
// DOM of the check before writing (issue 25 item 6): in the report, the verdict and the figures
// against their criteria (what fails in the danger colour; the core's statement of what fails and
// what would print the model is the error or the warning), with "Write it anyway" for a refused
// slice; in the view,
// the bar that shows or hides where it fails, with its legend (the colours of check-data.js, the
// counts drawn). No application state: the registry entry (check.js) calls these.
import { rgbCss } from '../colors.js';
import { figure } from '../format.js';
import { byTestId as $, fillFigureList } from '../panel-dom.js';
import { SKIPPED_COLOR } from './geodesic-view.js';
import { COLLISION_COLOR, UNSUPPORTED_COLOR, checkRows, checkVerdict, pointCountText } from './check-data.js';

/** The report's check (hidden without verify): verdict and figures; the button for a refused slice. */
export function fillCheckReport(v, { refused = false, busy = false } = {}) {
  $('check-report').hidden = !v;
  const verdict = checkVerdict(v, { refused });
  const p = $('check-verdict');
  p.textContent = verdict ? verdict.text : '—';
  if (verdict) p.dataset.state = verdict.state;
  else delete p.dataset.state;
  fillFigureList($('check-figures'), checkRows(v), 'check');
  const button = $('write-anyway');
  button.hidden = !(verdict && verdict.state === 'refused');
  button.disabled = busy;
}

/** The legend's colours, once. */
export function paintCheckLegend() {
  $('unsupported-dot').style.background = rgbCss(UNSUPPORTED_COLOR);
  $('collision-dot').style.background = rgbCss(COLLISION_COLOR);
  $('left-out-swatch').style.background = `#${SKIPPED_COLOR.toString(16).padStart(6, '0')}`;
}

/**
 * The view bar: shown when there is something to show (failing points, or left-out tool path the
 * geodesic view draws); each legend entry only for what is there.
 * @param {object|null} stats CheckView.stats()
 * @param {number} leftOut segments of left-out tool path drawn by the geodesic view
 */
export function fillCheckBar(stats, leftOut) {
  const unsupported = stats ? stats.unsupported : 0;
  const collisions = stats ? stats.collisions : 0;
  $('check-bar').hidden = !(unsupported || collisions || leftOut);
  $('legend-unsupported').hidden = !unsupported;
  $('unsupported-count').textContent = figure(unsupported);
  $('legend-collisions').hidden = !collisions;
  $('collision-count').textContent = stats ? pointCountText(collisions, stats.collisionsTotal) : '0';
  $('legend-left-out').hidden = !leftOut;
  $('left-out-count').textContent = `${figure(leftOut)} segment${leftOut === 1 ? '' : 's'}`;
}
