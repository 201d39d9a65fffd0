// SPDX-License-Identifier: MIT
// What a method needs of the machine, as the hint under the machine panel: the voxel, surface and
// geodesic methods tilt the nozzle (two rotary axes: table5 or head5, or a robot); the multidir
// method turns the part (or the head) between parts (one rotary axis is enough).

/** Machine kinds that can tilt the nozzle against the part. */
export const TILT_KINDS = Object.freeze(['table5', 'head4', 'head5', 'robot6']);

/** The hint for a method that tilts the nozzle (`doing`: what it does), '' when `kind` can. */
export function tiltHint(method, doing, kind) {
  return TILT_KINDS.includes(kind) ? '' : `the ${method} method ${doing}: choose table5, head4, head5 or a robot (${kind} has no tilt axes)`;
}

/** The hint for a method that turns the part between parts, '' when `kind` has a rotary axis. */
export function turnHint(method, kind) {
  return kind === 'cartesian3'
    ? `the ${method} method turns the part between parts: choose rotary4, table5, head4, head5 or a robot (cartesian3 has no rotary axis)` : '';
}
