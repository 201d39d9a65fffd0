// SPDX-License-Identifier: MIT
// The placement keys, named once. They say how the file's mesh becomes the part on the platform
// (repair, scale or fit, up axis, turns, centring); the core repairs and places the mesh with them
// before any method runs. A change
// of one of them is a placement change (the model is placed and drawn again, the old tool paths
// no longer match it); a change of any other setting is a slicing change. Used by the settings
// model (what a load and a slice request carry), the page (what an edit triggers) and the
// embedding module (which of a caller's settings place the mesh).

/** Settings keys that describe the placement (the rest are slicing settings). */
export const PLACEMENT_KEYS = Object.freeze(['repair', 'scale', 'fit_mm', 'up', 'rotate_x_deg', 'rotate_y_deg', 'rotate_z_deg', 'center']);

/** True when `key` is a placement key. */
export function isPlacementKey(key) {
  return PLACEMENT_KEYS.includes(key);
}

/** The placement keys present in a settings object, as a placement object for slicer.loadMesh(). */
export function placementOf(settings) {
  return Object.fromEntries(PLACEMENT_KEYS.filter((k) => k in settings).map((k) => [k, settings[k]]));
}
