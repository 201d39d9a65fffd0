// SPDX-License-Identifier: MIT
// The check before writing (issue 25 item 6) in the registry (index.js), beside the methods:
// every multi-axis result's program was simulated by the core exactly as `omnislice verify` does
// before it was delivered, and refused when it is not sound. Whatever the method, the report
// shows the verdict and the figures (check-panel.js) and the view draws where it fails
// (CheckView: unsupported and colliding tips; the geodesic view draws the left-out tool path, and
// the bar's toggle shows or hides it too). A refused slice is shown as a result without a program
// (app.refused, main.js); its "Write it anyway" sets verify = warn through the settings history
// and slices again.
import { timed } from '../block-runner.js';
import { byTestId as $ } from '../panel-dom.js';
import { SetSettingCommand } from '../settings-panel.js';
import { checkDoneSummary, checkRows, checkVerdict, hasCheckPoints, verifySection } from './check-data.js';
import { fillCheckBar, fillCheckReport, paintCheckLegend } from './check-panel.js';
import { CheckView } from './check-view.js';

/** Slice again with verify = warn (an undoable settings edit): the program comes with the statement as a warning. */
async function writeAnyway(app) {
  if (app.busy || !app.mesh) return;
  if (app.model.get('verify') !== 'warn') app.history.execute(new SetSettingCommand(app.model, 'verify', 'warn'));
  await app.actions.slice();
}

/** Left-out segments the geodesic view holds (drawn in its colour; the check bar lists them). */
function leftOutSegments(app) {
  return app.views.geodesic ? app.views.geodesic.skippedCount : 0;
}

/** The failing points and the left-out tool path follow the bar's checkbox. */
function applyVisible(app) {
  const shown = $('show-check').checked;
  if (app.views.check) app.views.check.setVisible(shown);
  if (app.views.geodesic) app.views.geodesic.setVisible('skipped', shown);
  fillCheckBar(app.views.check ? app.views.check.stats() : null, leftOutSegments(app));
  app.viewer && app.viewer.requestRender();
}

export const check = {
  name: 'check',
  data: {
    section: verifySection,
    summaryRows: checkRows,
    doneSummary: checkDoneSummary,
    hasView: hasCheckPoints,
  },
  panel: {
    show(app, v) {
      fillCheckReport(v, { refused: !!app.refused, busy: !!app.busy });
    },
    wire(app) {
      paintCheckLegend();
      $('write-anyway').addEventListener('click', () => writeAnyway(app));
      $('show-check').addEventListener('change', () => applyVisible(app));
    },
    enable(app) {
      $('write-anyway').disabled = !app.slicer || !app.mesh || !!app.busy;
    },
  },
  view: {
    build: (result) => timed('check-view', () => new CheckView(result.preview, verifySection(result.report))),
    /**
     * A new result shows where it fails when it is not sound; a sound one keeps its few tolerated
     * points (under 1 % of the surface) behind the toggle, so a sound print does not look alarming.
     */
    setup(app, { fresh = false } = {}) {
      if (fresh) {
        const shown = app.result || app.refused;
        const v = verifySection(shown && shown.report);
        $('show-check').checked = !(v && checkVerdict(v, { refused: !!app.refused }).state === 'sound');
      }
      applyVisible(app);
    },
    /** What the check shows: the verdict's state, whether the slice was refused, the points drawn. */
    inspect(app) {
      const shown = app.result || app.refused;
      const v = verifySection(shown && shown.report);
      if (!v) return null;
      const verdict = checkVerdict(v, { refused: !!app.refused });
      return {
        state: verdict.state,
        refused: !!app.refused,
        rows: Object.fromEntries(checkRows(v).map(([key, , text, state]) => [key, { text, state }])),
        points: app.views.check ? app.views.check.stats() : null,
        leftOut: leftOutSegments(app),
      };
    },
  },
};
