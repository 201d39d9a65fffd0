// SPDX-License-Identifier: MIT
// The registry of slicing methods: one module per method, each of the same shape
// {name, data, panel, view} (MethodModule below), and the loops the page runs over them. The page
// (main.js) calls these instead of asking which method a result came from: every method draws its
// report section when the report has it, and its view when the preview buffers carry it (a
// geodesic result, for one, also has the voxel view's layer surfaces; the surface method's
// iso-planar section also shows for any method's fill = isoplanar). A new method is a new module
// listed in METHODS.
//
// The modules keep their page state in the app state they are handed (main.js): app.views[name]
// is the method's current view object, app.result the shown result, app.busy, app.viewer, ...;
// app.actions are the page's operations a panel may start (slice, runSlice, setPreview,
// applyLayerRange, updateButtons).
//
// Beside the methods, the registry holds what every result shows whatever its method, in the same
// shape without a method's own data (stage weights, settings group, machine hint): the check
// before writing (check.js). The page's loops over report groups, panels and views run over both
// (SHOWN); what belongs to a method (its stages, hints, settings) only over METHODS.
import { auto } from './auto.js';
import { check } from './check.js';
import { geodesic } from './geodesic.js';
import { multidir } from './multidir.js';
import { planar } from './planar.js';
import { surface } from './surface.js';
import { voxel } from './voxel.js';

/**
 * @typedef {object} MethodModule
 * @property {string} name  the `method` setting's value (settings-fields.js 'method' options)
 * @property {object} data  pure functions of the report and the preview buffers (Node-tested):
 *   - stageWeights {stage: share}: the progress stages in pipeline order, shares summing to 1
 *   - settingsGroup string: the group of the method's own settings in settings-fields.js
 *   - section(report) -> object | null: the report section the panel draws
 *   - summaryRows(section) -> [key, label, text][]: its figures
 *   - doneSummary(section) -> string: the line after 'done in … s: ' ('' for none)
 *   - machineHint(kind) -> string: what the method lacks on a machine of that kind ('' nothing)
 *   - hasView?(preview) -> boolean: the preview buffers carry the method's view
 *   - progressDetail?(search) -> string: a progress event's search level as text
 * @property {object} panel  the method's report group and controls in the DOM:
 *   - show(app, section): fill the group from a section; null hides or clears it
 *   - wire(app): listeners on its controls, once at start-up
 *   - enable?(app): its buttons follow app.busy
 *   - reset?(app): a new result or model: forget the method's extra runs
 *   - showLayer?(app, layer): the top layer shown changed
 *   - showProgress?(app, progress): a running slice's progress (status-panel.js newProgress)
 *   - sliceFailed?(app, progress): a slice failed or was cancelled
 * @property {object} view  the method's three.js objects:
 *   - build?(result) -> view | Promise<view>: when data.hasView(result.preview); a view has
 *     .object (THREE.Object3D), stats(), and dispose() when it owns GPU buffers the viewer does
 *     not free
 *   - essential?: true when a failed build fails showing the result (else the error is shown
 *     as '<name> view: …' and the rest of the result still shows)
 *   - setup(app, {fresh}): after new views: its bar follows app.views[name] (hidden without one);
 *     fresh: a new result, not a switch between compared runs
 *   - setLayerRange?(app, lo, hi, atTop): the layer sliders' range (atTop: hi is the last layer)
 *   - inspect?(app) -> object | null: what it shows, for diagnostics and tests
 */

/** The methods in the page's drawing order (the tool paths first; views are added in this order). */
export const METHODS = Object.freeze([planar, voxel, surface, geodesic, multidir, auto]);

/** What every result shows besides its method's parts (check.js), drawn after the methods' views. */
export const EXTRAS = Object.freeze([check]);

/** The modules whose report groups, panels and views the page shows, in drawing order. */
const SHOWN = Object.freeze([...METHODS, ...EXTRAS]);

export { auto, check, geodesic, multidir, planar, surface, voxel };

/** The module of a method name; planar for a name it does not know. */
export function methodNamed(name) {
  return METHODS.find((m) => m.name === name) || planar;
}

/** Every method's stage weights by name. */
export const STAGE_WEIGHTS = Object.freeze(Object.fromEntries(METHODS.map((m) => [m.name, m.data.stageWeights])));

/** What a method needs of a machine of `kind`, as a hint ('' when the machine has it). */
export function machineHint(method, kind) {
  return methodNamed(method).data.machineHint(kind);
}

/** A progress event's search level as text (its stage's detail), '' when no method tells it. */
export function progressDetail(search) {
  for (const m of METHODS) {
    const text = m.data.progressDetail ? m.data.progressDetail(search) : '';
    if (text) return text;
  }
  return '';
}

/**
 * The line after 'done in … s: ' for a report: its method section's summary (a report has at
 * most one of the voxel, geodesic and multidir sections), then the check's verdict ('sound'),
 * joined by ' · '; '' for none.
 */
export function doneSummary(report) {
  const parts = [];
  // method = auto says which it chose first; then the chosen method's own line.
  const choice = auto.data.doneSummary(auto.data.section(report));
  if (choice) parts.push(choice);
  const method = METHODS.filter((m) => m !== auto).map((m) => m.data.doneSummary(m.data.section(report))).find((text) => text);
  if (method) parts.push(method);
  for (const m of EXTRAS) {
    const text = m.data.doneSummary(m.data.section(report));
    if (text) parts.push(text);
  }
  return parts.join(' · ');
}

/** Every method's report group shows the report (null clears them). */
export function showReports(app, report) {
  for (const m of SHOWN) m.panel.show(app, m.data.section(report));
}

/** Every method's controls, once at start-up. */
export function wirePanels(app) {
  for (const m of SHOWN) m.panel.wire(app);
}

/** The methods' buttons follow app.busy. */
export function enablePanels(app) {
  for (const m of SHOWN) if (m.panel.enable) m.panel.enable(app);
}

/** A new result or model: the methods forget their extra runs. */
export function resetPanels(app) {
  for (const m of SHOWN) if (m.panel.reset) m.panel.reset(app);
}

/** A running slice's progress, painted once per frame. */
export function showProgress(app, progress) {
  for (const m of SHOWN) if (m.panel.showProgress) m.panel.showProgress(app, progress);
}

/** A slice failed or was cancelled. */
export function sliceFailed(app, progress) {
  for (const m of SHOWN) if (m.panel.sliceFailed) m.panel.sliceFailed(app, progress);
}

/**
 * Build the views of a result's preview buffers, in METHODS order: {name: view}. A method's
 * failure is reported through onError(err) ('<name> view: …') and leaves its view out, except an
 * essential view's, which rejects.
 */
export async function buildViews(result, { onError }) {
  const views = {};
  const buffers = result && result.preview;
  if (!buffers) return views;
  for (const m of SHOWN) {
    if (!m.view.build || !m.data.hasView(buffers)) continue;
    try {
      views[m.name] = await m.view.build(result);
    } catch (err) {
      if (m.view.essential) throw err;
      onError({ code: 'internal', message: `${m.name} view: ${err.message}` });
    }
  }
  return views;
}

/**
 * One object for the viewer: the first view's object with the others' inside (null without
 * views).
 */
export function viewRoot(views) {
  const objects = SHOWN.filter((m) => views[m.name]).map((m) => views[m.name].object);
  for (const o of objects.slice(1)) objects[0].add(o);
  return objects[0] || null;
}

/** Free what the views own (the viewer frees the objects it was given). */
export function disposeViews(views) {
  for (const m of SHOWN) if (views[m.name] && views[m.name].dispose) views[m.name].dispose();
}

/** After new views (app.views): every method's bar follows its view. */
export function setupViews(app, options) {
  for (const m of SHOWN) m.view.setup(app, options);
}

/** The layer sliders' range lo..hi (atTop: hi is the last layer) for every view and panel. */
export function setLayerRange(app, lo, hi, atTop) {
  for (const m of SHOWN) {
    if (m.view.setLayerRange) m.view.setLayerRange(app, lo, hi, atTop);
    if (m.panel.showLayer) m.panel.showLayer(app, hi);
  }
}
