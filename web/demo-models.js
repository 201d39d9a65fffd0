// SPDX-License-Identifier: MIT
// The bundled demo models of the model menu (web/models, made by scripts/make-demo-*.mjs): where
// each is fetched from, the settings it is shown with and the machine it needs; and the one the
// page opens with.

/**
 * Demo models by the menu's option value: url, file name, settings (set through the history) and
 * tilt (a built-in machine with tilt axes, chosen when the selected machine has none).
 */
export const DEMOS = {
  // A post with three arms 20° above the horizontal (scripts/make-demo-arms.mjs), made to show what
  // multi-axis printing buys: with method = auto on table5 the page compares planar layers (with
  // supports under every arm) against multidir, geodesic and voxel side by side, and writes the
  // best verified program (multidir, nearly no support: README.md has the figures).
  arms: { url: '/models/demo-arms.obj', name: 'demo-arms.obj', settings: { method: 'auto' }, tilt: 'table5' },
  // A parametric overhang test piece (scripts/make-demo-model.mjs): overhangs at 30/45/60° and a
  // bridge, in planar layers on the machine selected.
  overhang: { url: '/models/demo-overhang.stl', name: 'demo-overhang.stl', settings: { method: 'planar' } },
  // An open saddle z = (x^2 - y^2) / R: the surface method's iso-planar paths (paper 003, S1).
  // The surface method needs tilt axes: a 3- or 4-axis machine is swapped for the UR5 arm.
  saddle: { url: '/models/demo-saddle.obj', name: 'demo-saddle.obj', settings: { method: 'surface' }, tilt: 'robot6-ur5' },
  // A trunk forking into three tilted branches (scripts/make-demo-tree.mjs): the geodesic
  // method's curved layers, skeleton tree and print sequences (paper 002). At a 45° nozzle angle
  // DPT collides while A3 stays collision-free with a tenth of LPT's retractions (README.md).
  tree: {
    url: '/models/demo-tree.obj', name: 'demo-tree.obj', tilt: 'table5',
    settings: { method: 'geodesic', nozzle: 0.8, 'geodesic.interval_mm': 0.8, 'geodesic.nozzle_angle_deg': 45, 'geodesic.sequence': 'a3' },
  },
};

/** The demo the page opens with, unless its address names another (`?demo=overhang`). */
export const FIRST_DEMO = 'arms';

/** The demo of a page address's query (`?demo=NAME`, a key of DEMOS), else FIRST_DEMO's. */
export function demoOfQuery(search) {
  const wanted = new URLSearchParams(search).get('demo');
  return DEMOS[wanted !== null && Object.hasOwn(DEMOS, wanted) ? wanted : FIRST_DEMO];
}
