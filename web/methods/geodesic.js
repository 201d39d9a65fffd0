// SPDX-License-Identifier: MIT
// The geodesic method (paper 002) in the registry (index.js): a tet mesh, the heat-method geodesic
// field, iso-geodesic distance surfaces (IGDS) as curved layers, the skeleton tree and a print
// sequence. Its report group (geodesic-panel.js): the figures, the overhang chart per layer (a mark
// at the shown top layer) and the traversal table, whose buttons slice again with another
// sequence. Its view (GeodesicView, geodesic-view.js): the distance field on the part, the tree
// and the air moves up to the print step; the IGDS are drawn by the voxel view's layer surfaces.
import { timed } from '../block-runner.js';
import { figure, formatMm } from '../format.js';
import { byTestId as $, setSliderRange } from '../panel-dom.js';
import { SetSettingCommand } from '../settings-panel.js';
import { GEODESIC_STAGE_WEIGHTS, geodesicDoneSummary, geodesicSummaryRows, hasGeodesicBuffers, rampCss } from './geodesic-data.js';
import { drawOverhangChart, fillGeoFigures, fillTraversalTable, setChartLayer } from './geodesic-panel.js';
import { GeodesicView } from './geodesic-view.js';
import { tiltHint } from './machine-needs.js';

/** Slice again with another print sequence (an undoable settings edit, then a slice). */
async function chooseSequence(app, name) {
  if (app.busy || !app.mesh) return;
  if (app.model.get('geodesic.sequence') !== name) app.history.execute(new SetSettingCommand(app.model, 'geodesic.sequence', name));
  await app.actions.slice();
}

/** The step and field texts follow the view (and the slider's data-* counts, for tests). */
function showStats(app) {
  const v = app.views.geodesic;
  if (!v) return;
  const s = v.stats();
  const c = s.current;
  $('geo-step-text').textContent = s.nodes
    ? `${s.step + 1} of ${s.nodes}${c ? ` (layer ${c.layer + 1})` : ''}` : 'no tree';
  $('field-range').textContent = `${formatMm(s.fieldMin)}–${formatMm(s.fieldMax)} mm`;
  $('air-count').textContent = s.airDrawn === s.airMoves ? String(s.airMoves) : `${s.airDrawn} / ${s.airMoves}`;
  const slider = $('geo-step-slider');
  slider.dataset.fieldDrawn = String(s.fieldDrawn);
  slider.dataset.nodesDrawn = String(s.nodesDrawn);
  slider.dataset.airDrawn = String(s.airDrawn);
  app.viewer && app.viewer.requestRender();
}

/** Show the tree as printed up to the step slider's position; the texts follow. */
function applyStep(app) {
  const v = app.views.geodesic;
  if (!v) {
    $('geo-step-text').textContent = '—';
    $('field-range').textContent = '—';
    $('air-count').textContent = '0';
    return;
  }
  v.setStep(Number($('geo-step-slider').value));
  showStats(app);
}

function setLayerVisible(app, kind, visible) {
  if (!app.views.geodesic) return;
  app.views.geodesic.setVisible(kind, visible);
  showStats(app);
}

/** @type {import('./index.js').MethodModule} */
export const geodesic = {
  name: 'geodesic',
  data: {
    stageWeights: GEODESIC_STAGE_WEIGHTS,
    settingsGroup: 'Geodesic',
    section: (report) => (report && report.geodesic && typeof report.geodesic === 'object' ? report.geodesic : null),
    summaryRows: geodesicSummaryRows,
    doneSummary: geodesicDoneSummary,
    machineHint: (kind) => tiltHint('geodesic', 'tilts the nozzle', kind),
    hasView: hasGeodesicBuffers,
  },
  panel: {
    /** The geodesic figures, overhang chart and traversal table (hidden without report.geodesic). */
    show(app, g) {
      $('geo-report').hidden = !g;
      fillGeoFigures($('geo-figures'), g);
      fillTraversalTable($('geo-traversal-table').querySelector('tbody'), g,
        { onChoose: (name) => chooseSequence(app, name), disabled: !!app.busy });
      const chart = drawOverhangChart($('geo-overhang-chart'), g, { layer: g ? Number($('layer-slider').value) : null });
      const stats = $('geo-chart-stats');
      if (!chart) stats.textContent = '—';
      else if (chart.error) stats.textContent = `(${chart.error})`;
      else stats.textContent = `${chart.layers} layers, largest ${figure(chart.maxValue)}°, ${chart.over} above 45°`;
    },
    wire(app) {
      $('show-field').addEventListener('change', (e) => setLayerVisible(app, 'field', e.target.checked));
      $('show-tree').addEventListener('change', (e) => setLayerVisible(app, 'tree', e.target.checked));
      $('show-air').addEventListener('change', (e) => setLayerVisible(app, 'air', e.target.checked));
      $('geo-step-slider').addEventListener('input', () => applyStep(app));
    },
    enable(app) {
      for (const b of document.querySelectorAll('[data-testid^="geo-use-"]')) b.disabled = !app.slicer || !app.mesh || !!app.busy;
    },
    /** The overhang chart marks the shown top layer (none without tool paths). */
    showLayer(app, layer) {
      setChartLayer($('geo-overhang-chart'), app.views.planar ? layer : null);
    },
  },
  view: {
    build: (result) => timed('geodesic-view', () => new GeodesicView(result.preview, result.report && result.report.geodesic)),
    /** The geodesic bar follows the new view (hidden without one). */
    setup(app) {
      const v = app.views.geodesic;
      $('geo-bar').hidden = !v;
      // The voxel bar's missed and support cells mean nothing for the geodesic method.
      for (const id of ['show-missed', 'show-support']) $(id).closest('label').hidden = !!v;
      setSliderRange($('geo-step-slider'), v ? v.nodeCount : 0);
      $('field-ramp').style.background = rampCss();
      if (v) {
        v.setVisible('field', $('show-field').checked);
        v.setVisible('tree', $('show-tree').checked);
        v.setVisible('air', $('show-air').checked);
      }
      applyStep(app);
    },
    /** At the slider's top the whole field and tree show, also the layers above the last printed one. */
    setLayerRange(app, lo, hi, atTop) {
      if (!app.views.geodesic) return;
      app.views.geodesic.setLayerRange(lo, atTop ? Number.MAX_SAFE_INTEGER : hi);
      showStats(app);
    },
    inspect: (app) => (app.views.geodesic ? app.views.geodesic.stats() : null),
  },
};
