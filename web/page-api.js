// SPDX-License-Identifier: MIT
// window.omnislice: a read-only view of the page for diagnostics and the end-to-end tests (what is
// loaded, the last report, what each view draws, the progress of the last slice), and one test
// hook that shows a made-up result as if the engine had produced it.
import { check, geodesic, multidir, surface, voxel } from './methods/index.js';
import { stageTimes } from './status-panel.js';

/** Install window.omnislice over the app state (main.js); app.actions.showResult draws a result. */
export function installPageApi(app) {
  window.omnislice = {
    get state() { return document.body.dataset.state; },
    get report() { return app.result ? app.result.report : null; },
    /** The report of the refused slice shown (error unsound_program; no program), or null. */
    get refusedReport() { return app.refused ? app.refused.report : null; },
    get info() { return app.mesh ? app.mesh.info : null; },
    /** The model drawn: {faces, filledFaces (holes the repair closed, in their own colour), filledColor} or null. */
    get model() {
      const m = app.viewer && app.viewer.model;
      if (!m) return null;
      const index = m.geometry.index;
      return {
        faces: index ? index.count / 3 : m.geometry.attributes.position.count / 3,
        filledFaces: m.userData.filledFaces || 0,
        filledColor: Array.isArray(m.material) ? `#${m.material[1].color.getHexString()}` : null,
      };
    },
    get previewSegments() { return app.views.planar ? app.views.planar.segmentCount : 0; },
    get featureCounts() { return app.views.planar ? app.views.planar.featureCounts : null; },
    get drawnSegments() { return app.views.planar ? app.views.planar.drawnSegments() : [0, 0]; },
    get settings() { return app.model ? app.model.toSettings() : null; },
    /** Workers method = auto runs its candidates in (the slicer's pool). */
    get workers() { return app.slicer ? app.slicer.workers : 0; },
    get history() { return app.history.serialize(); },
    get programExtension() { return app.result ? app.result.programExtension : null; },
    /**
     * The iso-planar view: {curveCount (NL curves drawn in alternating colours), shownRun,
     * compare: {theta, report} | null, rows (the comparison table)}, or null without report.isoplanar.
     */
    get isoplanar() { return surface.view.inspect(app); },
    /** The voxel view: what it holds and draws (VoxelView.stats()), or null. */
    get voxel() { return voxel.view.inspect(app); },
    /** The geodesic view: what it holds and draws (GeodesicView.stats()), or null. */
    get geodesic() { return geodesic.view.inspect(app); },
    /** The multidir view: what it holds and draws (MultidirView.stats()), or null. */
    get multidir() { return multidir.view.inspect(app); },
    /**
     * The check before writing: {state (sound, warned, refused, unsound), refused, rows {key: {text,
     * state}}, points (CheckView.stats()) | null, leftOut (segments)}, or null without report.verify.
     */
    get check() { return check.view.inspect(app); },
    /**
     * The search levels of the last slice's multidir decomposition: {levels: progress.search of
     * every event in arrival order, liveDraws: the live J_G chart's values at each of its drawings}.
     */
    get searchProgress() {
      return { levels: app.progress.levels.map((s) => ({ ...s })), liveDraws: app.progress.liveDraws.map((v) => v.slice()) };
    },
    /** The stage details of the last slice (a search level's text for 'decompose'): {stage: text}. */
    get stageDetails() {
      return Object.fromEntries([...app.progress.stages].filter(([, e]) => e.detail).map(([k, e]) => [k, e.detail]));
    },
    /** The progress stages of the last slice in arrival order: [[stage, fraction, ms]]. */
    get stages() {
      return stageTimes(app.progress).map(([stage, e, ms]) => [stage, e.fraction, ms]);
    },
    /**
     * Test hook: show a result object shaped like slicer.slice()'s (programBytes, programExtension,
     * report, preview, mesh) as if the engine had produced it; resolves when it is drawn.
     */
    async _showResultForTest(result) {
      if (app.busy) throw new Error('busy');
      try {
        await app.actions.showResult(result, performance.now());
      } finally {
        app.busy = null;
        app.actions.updateButtons();
      }
    },
    /** The machine animation: {kind, step, steps, tipError (mm, measured in the scene)} or null. */
    get machine() {
      const v = app.machineView;
      return v ? { kind: v.kind, step: v.step, steps: v.stepCount, tipError: v.tipError, replay: app.replay ? app.replay.name : null } : null;
    },
  };
}
