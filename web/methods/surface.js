// SPDX-License-Identifier: MIT
// The surface method (paper 003) in the registry (index.js): an open surface printed as one layer
// of iso-planar paths on a planar base. Its report group is the iso-planar one, which also shows
// for any method's fill = isoplanar (report.isoplanar): the figures, the polar plot of the
// deposition rate v_e(theta) with theta*, and a comparison run (the same settings with theta
// forced to another direction; app.compare) side by side with the first, either one's paths
// drawn (app.shownRun). The NL curves themselves are drawn by the tool-path preview (planar.js),
// in alternating colours.
import { rgbCss } from '../colors.js';
import { figure } from '../format.js';
import { byTestId as $ } from '../panel-dom.js';
import { setPageState, setProgressText, showError, showStages } from '../status-panel.js';
import { CURVE_COLORS, SURFACE_STAGE_WEIGHTS, comparisonRows, foldTheta, isoplanarSummaryRows, sideStepText } from './isoplanar-data.js';
import { drawPolarPlot, fillCompareTable, fillIsoFigures, plotThetaAt } from './isoplanar-panel.js';
import { tiltHint } from './machine-needs.js';

const section = (report) => (report && report.isoplanar && typeof report.isoplanar === 'object' ? report.isoplanar : null);

/** The iso-planar report of the first run (app.result), or null. */
function firstIso(app) {
  return section(app.result && app.result.report);
}

/** The direction the compare input holds, folded into [0, 180), or null when it is not a number. */
function compareTheta() {
  const text = $('iso-compare-theta').value.trim();
  const x = Number(text);
  return text !== '' && Number.isFinite(x) ? foldTheta(x) : null;
}

/**
 * The polar plot of the first run, with the compared direction: the compared run's (and the
 * input's as the next candidate when it differs), else the input's.
 */
function renderPolar(app, iso) {
  const input = compareTheta();
  const options = app.compare
    ? { compareTheta: app.compare.theta, candidateTheta: input !== null && input !== app.compare.theta ? input : null }
    : { compareTheta: input };
  const star = drawPolarPlot($('iso-polar'), iso, options);
  const ok = star && !star.error;
  $('iso-theta-star').textContent = ok ? `${figure(star.theta)}°${iso.forced ? ' (forced)' : ''}` : star ? `(${star.error})` : '—';
  $('iso-ve-star').textContent = ok && Number.isFinite(star.value) ? `${figure(star.value)} mm³/s` : '—';
}

/** The iso-planar runs for the comparison table: the first (app.result), the compared one. */
function compareRuns(app) {
  const iso = firstIso(app);
  if (!iso) return [];
  const runs = [{ label: iso.forced ? 'first run (forced θ)' : 'first run (θ*)', report: app.result.report }];
  if (app.compare) runs.push({ label: 'compared run', report: app.compare.result.report });
  return runs;
}

function renderCompareTable(app) {
  fillCompareTable($('iso-compare-table').querySelector('tbody'), compareRuns(app));
}

/** Draw the paths of run k (0: the first result, 1: the compared run). */
async function showRun(app, k) {
  const run = k === 1 && app.compare ? app.compare.result : app.result;
  app.shownRun = run === app.result ? 0 : 1;
  $('iso-show-run').value = String(app.shownRun);
  if (!run) return;
  await app.actions.setPreview(run);
}

/**
 * Slice again with the first run's settings and isoplanar.theta_deg forced to the compare input's
 * direction; the first result stays (report, download, paths); the table shows both runs side by
 * side. A failed comparison leaves the first result as it was.
 */
async function runCompare(app) {
  if (!app.slicer || !app.mesh || app.busy || !firstIso(app)) return;
  const theta = compareTheta();
  if (theta === null) {
    showError({ code: 'invalid_option', message: 'compare: give a direction θ in degrees, 0..180' });
    return;
  }
  // The first run's settings (later edits in the panel do not leak into the comparison).
  const settings = { ...(app.resultSettings || app.model.toSliceSettings()), 'isoplanar.theta_deg': theta };
  await app.actions.runSlice(settings, {
    startText: `comparing θ = ${figure(theta)}°`,
    failText: 'compare failed',
    async onResult(result, started) {
      app.compare = { theta, result };
      if (app.shownRun === 1) await showRun(app, 1);
      renderPolar(app, firstIso(app));
      renderCompareTable(app);
      $('iso-show-run').disabled = false;
      app.compareCount += 1;
      document.body.dataset.compareCount = String(app.compareCount);
      setProgressText(`compared θ = ${figure(theta)}° in ${((performance.now() - started) / 1000).toFixed(2)} s`, 1);
      showStages(app.progress, { finished: true });
      setPageState('done');
    },
  });
}

/** @type {import('./index.js').MethodModule} */
export const surface = {
  name: 'surface',
  data: {
    stageWeights: SURFACE_STAGE_WEIGHTS,
    settingsGroup: 'Iso-planar',
    section,
    summaryRows: isoplanarSummaryRows,
    doneSummary: () => '',
    machineHint: (kind) => tiltHint('surface', 'keeps the nozzle along the surface normal', kind),
  },
  panel: {
    /** The iso-planar figures, polar plot and comparison (hidden without report.isoplanar). */
    show(app, iso) {
      $('iso-report').hidden = !iso;
      // A new result proposes the direction square to theta* for the comparison.
      if (iso && !app.compare && Number.isFinite(iso.theta_deg)) $('iso-compare-theta').value = String(foldTheta(iso.theta_deg + 90));
      fillIsoFigures($('iso-figures'), iso);
      renderPolar(app, iso);
      renderCompareTable(app);
      $('iso-side-step').textContent = sideStepText(iso);
      $('iso-curve-swatch-odd').style.background = rgbCss(CURVE_COLORS[0]);
      $('iso-curve-swatch-even').style.background = rgbCss(CURVE_COLORS[1]);
    },
    wire(app) {
      // A click on the polar plot: the direction there goes to the compare input (and is marked).
      $('iso-polar').addEventListener('click', (e) => {
        const theta = plotThetaAt($('iso-polar'), e.clientX, e.clientY);
        if (theta === null) return;
        $('iso-compare-theta').value = String(theta);
        renderPolar(app, firstIso(app));
      });
      $('iso-compare-theta').addEventListener('input', () => renderPolar(app, firstIso(app)));
      $('iso-compare-button').addEventListener('click', () => runCompare(app));
      $('iso-show-run').addEventListener('change', (e) => {
        if (app.busy) return;
        app.busy = 'showing';
        app.actions.updateButtons();
        showRun(app, Number(e.target.value)).finally(() => {
          app.busy = null;
          app.actions.updateButtons();
        });
      });
    },
    enable(app) {
      $('iso-compare-button').disabled = !app.slicer || !app.mesh || !!app.busy || !firstIso(app);
      $('iso-show-run').disabled = !app.compare || !!app.busy;
    },
    /** Forget the comparison run (a new slice or model). */
    reset(app) {
      app.compare = null;
      app.shownRun = 0;
      const select = $('iso-show-run');
      select.value = '0';
      select.disabled = true;
    },
  },
  view: {
    /** The NL curves the tool-path preview draws: their count and legend entries. */
    setup(app) {
      const n = app.views.planar ? app.views.planar.curveCount : 0;
      $('iso-curve-count').textContent = String(n);
      for (const li of document.querySelectorAll('[data-testid="legend-curves"]')) li.hidden = !(n > 0);
    },
    /**
     * What the page shows of the iso-planar paths: {curveCount, shownRun, compare: {theta,
     * report} | null, rows (the comparison table)}, or null without report.isoplanar.
     */
    inspect(app) {
      if (!firstIso(app)) return null;
      return {
        curveCount: app.views.planar ? app.views.planar.curveCount : 0,
        shownRun: app.shownRun,
        compare: app.compare ? { theta: app.compare.theta, report: app.compare.result.report } : null,
        rows: comparisonRows(compareRuns(app)),
      };
    },
  },
};
