// SPDX-License-Identifier: MIT
// The voxel method (paper 001) in the registry (index.js): conservative voxels, a growing field,
// curved layers. Its report group: the figures and the layer-thickness histogram
// (voxel-panel.js). Its view (VoxelView, voxel-view.js): the curved layer surfaces up to the
// surface slider's layer, missed and support cells, nozzle-axis glyphs; the voxel bar's slider
// and toggles drive it, and the surface slider and the top layer slider follow each other. The
// geodesic method's results carry layer surfaces too (its IGDS), so this view shows for them as
// well.
import { rgbCss } from '../colors.js';
import { byTestId as $, setSliderRange } from '../panel-dom.js';
import { tiltHint } from './machine-needs.js';
import { VOXEL_STAGE_WEIGHTS, layerColor, voxelDoneSummary, voxelSummaryRows } from './voxel-data.js';
import { drawThicknessHistogram, fillVoxelFigures } from './voxel-panel.js';
import { VoxelView, hasVoxelBuffers } from './voxel-view.js';

/** Show the layer surfaces up to the surface slider's layer (that one highlighted). */
function applySurfaceLayer(app) {
  const v = app.views.voxel;
  const slider = $('layer-surface-slider');
  if (!v) {
    $('surface-layer-text').textContent = '—';
    delete slider.dataset.drawnTriangles;
    return;
  }
  const r = v.setSurfaceLayer(Number(slider.value));
  slider.value = String(r.hi);
  const stats = v.stats();
  slider.dataset.drawnTriangles = String(stats.drawnTriangles);
  $('surface-layer-text').textContent = v.surfaceLayerCount
    ? `${r.hi + 1} of ${v.surfaceLayerCount} (${stats.currentTriangles.toLocaleString('en')} triangles)` : 'no surfaces';
  app.viewer && app.viewer.requestRender();
}

function setLayerVisible(app, kind, visible) {
  if (!app.views.voxel) return;
  app.views.voxel.setVisible(kind, visible);
  if (kind === 'surfaces') applySurfaceLayer(app);
  app.viewer && app.viewer.requestRender();
}

/** CSS background of the layer colour ramp (the colours of layers spread over the count). */
function layerRampCss(L) {
  const stops = [];
  for (let k = 0; k < Math.min(L, 12); k++) {
    const l = Math.round((k * (L - 1)) / Math.max(Math.min(L, 12) - 1, 1));
    stops.push(rgbCss(layerColor(l, L)));
  }
  return stops.length > 1 ? `linear-gradient(to right, ${stops.join(', ')})` : stops[0] || 'none';
}

/** @type {import('./index.js').MethodModule} */
export const voxel = {
  name: 'voxel',
  data: {
    stageWeights: VOXEL_STAGE_WEIGHTS,
    settingsGroup: 'Voxel',
    section: (report) => (report && report.voxel && typeof report.voxel === 'object' ? report.voxel : null),
    summaryRows: voxelSummaryRows,
    doneSummary: voxelDoneSummary,
    machineHint: (kind) => tiltHint('voxel', 'tilts the nozzle', kind),
    hasView: hasVoxelBuffers,
  },
  panel: {
    show(app, v) {
      $('voxel-report').hidden = !v;
      drawThicknessHistogram($('thickness-histogram'), $('thickness-stats'), v && v.thickness);
      fillVoxelFigures($('voxel-figures'), v);
    },
    wire(app) {
      // The surfaces follow the tool-paths' top layer, and the tool paths (and glyphs) the
      // surfaces' layer.
      $('layer-slider').addEventListener('input', (e) => {
        if (!app.views.voxel) return;
        $('layer-surface-slider').value = e.target.value;
        applySurfaceLayer(app);
      });
      $('layer-surface-slider').addEventListener('input', (e) => {
        applySurfaceLayer(app);
        const hi = $('layer-slider');
        if (!hi.disabled) {
          hi.value = e.target.value;
          app.actions.applyLayerRange(hi);
        }
      });
      $('show-surfaces').addEventListener('change', (e) => setLayerVisible(app, 'surfaces', e.target.checked));
      $('show-missed').addEventListener('change', (e) => setLayerVisible(app, 'missed', e.target.checked));
      $('show-support').addEventListener('change', (e) => setLayerVisible(app, 'support', e.target.checked));
      $('axis-glyphs-toggle').addEventListener('change', (e) => setLayerVisible(app, 'glyphs', e.target.checked));
    },
  },
  view: {
    build: (result) => VoxelView.build(result.preview),
    /**
     * The surface slider and the voxel bar follow the new view (hidden without one). On a fresh
     * result the surfaces start hidden when the paths are iso-planar NL curves (the surface would
     * cover them), shown otherwise.
     */
    setup(app, { fresh = false } = {}) {
      const v = app.views.voxel;
      const preview = app.views.planar;
      if (fresh) $('show-surfaces').checked = !(preview && preview.curveCount > 0);
      $('voxel-bar').hidden = !v;
      setSliderRange($('layer-surface-slider'), v ? v.surfaceLayerCount : 0);
      const missed = $('missed-count');
      const reported = app.result && app.result.report && app.result.report.voxel ? app.result.report.voxel.missed_voxels : undefined;
      const count = Number.isFinite(reported) ? reported : v ? v.missedCount : 0;
      missed.textContent = count.toLocaleString('en');
      missed.classList.toggle('alert', count > 0);
      $('support-count').textContent = (v ? v.supportCount : 0).toLocaleString('en');
      $('layer-ramp').style.background = layerRampCss(v ? v.surfaceLayerCount : 0);
      if (v) {
        v.setVisible('surfaces', $('show-surfaces').checked);
        v.setVisible('missed', $('show-missed').checked);
        v.setVisible('support', $('show-support').checked);
        v.setVisible('glyphs', $('axis-glyphs-toggle').checked);
      }
      applySurfaceLayer(app);
    },
    setLayerRange(app, lo, hi) {
      if (app.views.voxel) app.views.voxel.setGlyphLayerRange(lo, hi);
    },
    inspect: (app) => (app.views.voxel ? app.views.voxel.stats() : null),
  },
};
