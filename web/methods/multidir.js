// SPDX-License-Identifier: MIT
// The multi-directional method (paper 000) in the registry (index.js): the part clipped by planes
// into parts, each printed as planar layers along its own direction. Its report group
// (multidir-panel.js): J_G before -> after, the parts table and the chart of J_G per search level,
// drawn live from the search's progress events while the decomposition runs. Its view
// (MultidirView, multidir-view.js): the parts in colours up to the order slider, direction
// arrows, the risky faces before or after.
import { timed } from '../block-runner.js';
import { byTestId as $, setSliderRange } from '../panel-dom.js';
import { turnHint } from './machine-needs.js';
import {
  MULTIDIR_STAGE_WEIGHTS, areaFigure, hasMultidirBuffers, liveJgLevels, multidirDoneSummary, multidirSummaryRows, searchLevelText,
} from './multidir-data.js';
import { drawJgChart, drawJgLevels, fillMultidirFigures, fillPartsTable } from './multidir-panel.js';
import { MultidirView } from './multidir-view.js';

const section = (report) => (report && report.multidir && typeof report.multidir === 'object' ? report.multidir : null);

/** The multidir figures, parts table and J_G chart (hidden without report.multidir). */
function show(app, m) {
  $('md-report').hidden = !m;
  fillMultidirFigures($('md-figures'), m);
  fillPartsTable($('md-parts-table').querySelector('tbody'), m);
  const chart = drawJgChart($('md-jg-chart'), m);
  const stats = $('md-chart-stats');
  if (!chart) stats.textContent = '—';
  else if (chart.error) stats.textContent = `(${chart.error})`;
  else stats.textContent = `${chart.points} levels, ${areaFigure(chart.first)} → ${areaFigure(chart.last)} mm²`;
}

/**
 * The J_G chart of a running decomposition, from its search levels so far (the report's chart
 * replaces it when the result comes). Its first drawing in a slice shows the multidir report
 * group and clears the previous result's figures and parts table.
 */
function showLiveSearch(p) {
  p.levelsDrawn = p.levels.length;
  const values = liveJgLevels(p.levels);
  if (values.length === 0) return;
  if (p.liveDraws.length === 0) {
    $('md-report').hidden = false;
    fillMultidirFigures($('md-figures'), null);
    fillPartsTable($('md-parts-table').querySelector('tbody'), null);
  }
  p.liveDraws.push(values);
  const chart = drawJgLevels($('md-jg-chart'), values, { live: true });
  $('md-chart-stats').textContent = chart && !chart.error
    ? `searching: ${chart.points} levels, ${areaFigure(chart.first)} → ${areaFigure(chart.last)} mm²` : '—';
}

function showStats(app) {
  const v = app.views.multidir;
  if (!v) return;
  const s = v.stats();
  $('md-order-text').textContent = s.parts ? `${s.order + 1} of ${s.parts}` : 'no parts';
  $('md-risky-text').textContent = s.risky === 'none' ? ''
    : `${s.riskyTriangles[s.risky]} faces, ${areaFigure(s.riskyAreaMm2[s.risky])} mm²`;
  const slider = $('md-order-slider');
  slider.dataset.partsShown = String(s.partsShown);
  slider.dataset.trianglesDrawn = String(s.trianglesDrawn);
  slider.dataset.arrowsDrawn = String(s.arrowsDrawn);
  app.viewer && app.viewer.requestRender();
}

/** Show the parts printed up to the order slider's position; the texts follow. */
function applyOrder(app) {
  const v = app.views.multidir;
  if (!v) {
    $('md-order-text').textContent = '—';
    $('md-risky-text').textContent = '—';
    return;
  }
  v.setOrder(Number($('md-order-slider').value));
  showStats(app);
}

function setOption(app, apply) {
  if (!app.views.multidir) return;
  apply(app.views.multidir);
  showStats(app);
}

/** @type {import('./index.js').MethodModule} */
export const multidir = {
  name: 'multidir',
  data: {
    stageWeights: MULTIDIR_STAGE_WEIGHTS,
    settingsGroup: 'Multi-directional',
    section,
    summaryRows: multidirSummaryRows,
    doneSummary: multidirDoneSummary,
    machineHint: (kind) => turnHint('multidir', kind),
    hasView: hasMultidirBuffers,
    progressDetail: searchLevelText,
  },
  panel: {
    show,
    wire(app) {
      $('show-parts').addEventListener('change', (e) => setOption(app, (v) => v.setVisible('parts', e.target.checked)));
      $('show-arrows').addEventListener('change', (e) => setOption(app, (v) => v.setVisible('arrows', e.target.checked)));
      $('md-risky').addEventListener('change', (e) => setOption(app, (v) => v.setRisky(e.target.value)));
      $('md-order-slider').addEventListener('input', () => applyOrder(app));
    },
    /**
     * The live J_G chart follows the search levels. The chosen sequence's levels come in a burst
     * at the end of decompose: drawn once the next stage starts, not one by one (the chart would
     * shrink to its first point).
     */
    showProgress(app, p) {
      const chosenComing = p.stage === 'decompose' && p.levels.at(-1)?.line === 'chosen';
      if (p.levels.length !== p.levelsDrawn && !chosenComing) showLiveSearch(p);
    },
    /** A live search chart goes: the report group shows the last result again. */
    sliceFailed(app, p) {
      if (p.liveDraws.length > 0) show(app, section(app.result && app.result.report));
    },
  },
  view: {
    build: (result) => timed('multidir-view', () => new MultidirView(result.preview, result.report && result.report.multidir, result.mesh)),
    /** The multidir bar follows the new view (hidden without one). */
    setup(app) {
      const v = app.views.multidir;
      $('md-bar').hidden = !v;
      setSliderRange($('md-order-slider'), v ? v.partCount : 0);
      if (v) {
        v.setVisible('parts', $('show-parts').checked);
        v.setVisible('arrows', $('show-arrows').checked);
        v.setRisky($('md-risky').value);
      }
      applyOrder(app);
    },
    inspect: (app) => (app.views.multidir ? app.views.multidir.stats() : null),
  },
};
