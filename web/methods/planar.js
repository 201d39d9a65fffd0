// SPDX-License-Identifier: MIT
// The planar method in the registry (index.js): layers along one direction, printed as tool
// paths. What it shows is what every result shows, so its panel and view stay on for every
// method: the report's general figures and warnings, the tool-path preview (ToolpathPreview:
// features in colours, layer range, travel toggle) and its legend. The other methods add their
// own section and view on top of these.
import { byTestId as $ } from '../panel-dom.js';
import { ToolpathPreview } from '../preview.js';
import { PLANAR_STAGE_WEIGHTS, reportRows } from './planar-data.js';
import { fillLegend, fillReportFigures, fillWarnings } from './planar-panel.js';

/** @type {import('./index.js').MethodModule} */
export const planar = {
  name: 'planar',
  data: {
    stageWeights: PLANAR_STAGE_WEIGHTS,
    settingsGroup: 'Slicing',
    /** The general figures are the report itself. */
    section: (report) => report || null,
    summaryRows: reportRows,
    doneSummary: () => '',
    machineHint: () => '',
    hasView: (preview) => !!(preview && preview.features && preview.features.length),
  },
  panel: {
    show(app, report) {
      fillReportFigures($('report'), report);
      fillWarnings($('report-warnings'), report);
    },
    wire(app) {
      fillLegend($('legend'));
      $('show-travel').addEventListener('change', (e) => {
        if (app.views.planar) app.views.planar.setTravelVisible(e.target.checked);
        app.viewer && app.viewer.requestRender();
      });
    },
  },
  view: {
    // The tool paths are the result: when they cannot be drawn, showing the result fails.
    essential: true,
    build: (result) => ToolpathPreview.build(result.preview),
    setup(app) {
      if (app.views.planar) app.views.planar.setTravelVisible($('show-travel').checked);
    },
    setLayerRange(app, lo, hi) {
      if (!app.views.planar) return;
      app.views.planar.setLayerRange(lo, hi);
      app.viewer && app.viewer.requestRender();
    },
  },
};
