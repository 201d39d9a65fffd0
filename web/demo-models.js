// SPDX-License-Identifier: MIT
// The bundled demo models of the model menu (web/models, made by scripts/make-demo-*.mjs): where
// each is fetched from, the settings it is shown with and the machine it needs.

/**
 * Demo models by the menu's option value: url, file name, settings (set through the history) and
 * tilt (a built-in machine with tilt axes, chosen when the selected machine has none).
 */
export const DEMOS = {
  overhang: { url: '/models/demo-overhang.stl', name: 'demo-overhang.stl' },
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
