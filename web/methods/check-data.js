// SPDX-License-Identifier: MIT
// Pure data of the check every multi-axis result carries (issue 25 item 6): before the program is
// delivered the core simulates it exactly as `omnislice verify` does and judges it sound or not
// (core/pipeline/soundness.h; the report's `verify` section). Here: the verdict, the figures
// against their criteria, and the failing points of the preview (tips of the unsupported and the
// colliding samples) as point clouds. Not a method: a part of every result, like the planar
// module's general figures. No three.js, no DOM; unit-tested in Node.
import { figure, formatLength, formatMs, plural } from '../format.js';

/**
 * The default criteria of a sound program, as core/pipeline/soundness.h SoundnessCriteria has
 * them. The report's verify.criteria gives the bounds judged against and wins; these serve a
 * report without them (recorded before they were written). Collisions, limits and left-out tool
 * path must be zero.
 */
export const SOUNDNESS_CRITERIA = Object.freeze({ inside: 0.99, coverage: 0.97, supported: 0.99, surface_reached: 0.99 });

/** Colours (0..255 RGB) of the failing points: apart from every feature colour and from each other. */
export const UNSUPPORTED_COLOR = Object.freeze([0xff, 0x2b, 0xd6]);
export const COLLISION_COLOR = Object.freeze([0x00, 0xe5, 0xff]);

/** The kinds of failing points: preview buffer, legend text, colour. */
export const FAILING_POINTS = Object.freeze([
  Object.freeze({ kind: 'unsupported', buffer: 'unsupportedPoints', label: 'printed over air', color: UNSUPPORTED_COLOR }),
  Object.freeze({ kind: 'collisions', buffer: 'collisionPoints', label: 'nozzle collision', color: COLLISION_COLOR }),
]);

/** The report's verify section, or null (absent when verify is off, and for planar by default). */
export function verifySection(report) {
  const v = report && report.verify;
  return v && typeof v === 'object' ? v : null;
}

/**
 * A share (0..1) as a percentage with one decimal, more when one would round a failing share up
 * to its bound (0.98996 against 0.99 reads '98.996 %', not '99.0 %').
 */
export function shareText(value, min) {
  if (!Number.isFinite(value)) return '—';
  const p = value * 100;
  let digits = 1;
  while (digits < 4 && Number.isFinite(min) && value < min && Number(p.toFixed(digits)) >= min * 100) digits++;
  return `${p.toFixed(digits)} %`;
}

/** 'none' for zero, else the count with its word. */
function countText(n, word) {
  if (!Number.isFinite(n)) return '—';
  return n === 0 ? 'none' : plural(n, word);
}

/**
 * Rows [key, label, text, state] of the check's figures in display order (keys double as
 * data-testid suffixes: check-<key>); state 'pass' or 'fail' against the criteria, '' for a
 * figure that is not judged. Coverage is listed only where it is judged (a solid fill).
 */
export function checkRows(v) {
  if (!v) return [];
  const given = v.criteria && typeof v.criteria === 'object' ? v.criteria : {};
  const c = {};
  for (const key of Object.keys(SOUNDNESS_CRITERIA)) {
    c[key] = Number.isFinite(given[key]) ? given[key] : SOUNDNESS_CRITERIA[key];
  }
  const state = (ok) => (ok === null ? '' : ok ? 'pass' : 'fail');
  const atLeast = (x, min) => (Number.isFinite(x) ? state(x >= min) : '');
  const zero = (x) => (Number.isFinite(x) ? state(x === 0) : '');
  const bound = (x, min) => (Number.isFinite(x) ? `${shareText(x, min)} (≥ ${figure(min * 100)} %)` : '—');
  const leftOut = Number.isFinite(v.left_out_mm) ? v.left_out_mm : NaN;
  const rows = [
    ['inside', 'inside the part', bound(v.inside, c.inside), atLeast(v.inside, c.inside)],
  ];
  if (v.coverage_judged) rows.push(['coverage', 'interior filled', bound(v.coverage, c.coverage), atLeast(v.coverage, c.coverage)]);
  if (Number.isFinite(v.surface_reached)) {
    rows.push(['surface_reached', 'surface printed', bound(v.surface_reached, c.surface_reached),
      atLeast(v.surface_reached, c.surface_reached)]);
  }
  rows.push(
    ['supported', 'surface supported', bound(v.supported, c.supported), atLeast(v.supported, c.supported)],
    ['collisions', 'nozzle collisions', countText(v.collisions, 'sample'), zero(v.collisions)],
    ['limits', 'axis limits exceeded', countText(v.limits, 'move'), zero(v.limits)],
    ['left_out', 'path left out', Number.isFinite(leftOut) ? (leftOut === 0 ? 'none' : formatLength(leftOut)) : '—',
      Number.isFinite(leftOut) ? state(leftOut === 0) : ''],
    ['simulated', 'simulated', Number.isFinite(v.samples)
      ? `${plural(v.samples, 'sample')}${Number.isFinite(v.ms) ? `, ${formatMs(v.ms)}` : ''}` : '—', ''],
  );
  const attempts = attemptsText(v.attempts);
  if (attempts) rows.push(['attempts', 'made again', attempts, '']);
  return rows;
}

/**
 * The programs the core made again after the one of the user's settings was unsound (the
 * report's verify.attempts: [{settings, sound}]), e.g. "voxel.smooth=10: not sound; voxel.smooth=40:
 * sound (delivered)"; '' without any.
 */
export function attemptsText(attempts) {
  if (!Array.isArray(attempts) || attempts.length === 0) return '';
  return attempts.map((a) => `${a && a.settings ? a.settings : '?'}: ${a && a.sound ? 'sound (delivered)' : 'not sound'}`)
    .join('; ');
}

/**
 * The verdict of a check: {state, text}. state: 'sound'; 'refused' (not sound, no program:
 * the slice was refused); 'warned' (not sound, written anyway: verify = warn); 'unsound' (not
 * sound, delivered otherwise). refused: the result is a refused slice's (its error's report).
 */
export function checkVerdict(v, { refused = false } = {}) {
  if (!v) return null;
  if (v.sound && !refused) return { state: 'sound', text: 'Sound: the simulated program meets every criterion.' };
  if (refused) return { state: 'refused', text: 'Not sound: no program was written.' };
  if (v.mode === 'warn') return { state: 'warned', text: 'Not sound: written anyway (verify = warn).' };
  return { state: 'unsound', text: 'Not sound.' };
}

/** The line after 'done in … s: ' for the check ('' without one). */
export function checkDoneSummary(v) {
  if (!v) return '';
  return v.sound ? 'sound' : 'not sound';
}

/**
 * The finite xyz triples of a preview point buffer (#N*3, part frame, mm) as a Float32Array:
 * the buffer itself when all are finite, else a copy without the others. null or absent: empty.
 * @throws Error when it is not a Float32Array of whole triples
 */
export function pointCloud(buffer, name = 'points') {
  if (buffer == null) return new Float32Array(0);
  if (!(buffer instanceof Float32Array)) throw new Error(`check view: ${name} is not a Float32Array`);
  if (buffer.length % 3 !== 0) throw new Error(`check view: ${name} has ${buffer.length} values, not whole xyz triples`);
  let finite = 0;
  for (let k = 0; k < buffer.length; k += 3) {
    if (Number.isFinite(buffer[k]) && Number.isFinite(buffer[k + 1]) && Number.isFinite(buffer[k + 2])) finite++;
  }
  if (3 * finite === buffer.length) return buffer;
  const out = new Float32Array(3 * finite);
  let j = 0;
  for (let k = 0; k < buffer.length; k += 3) {
    if (Number.isFinite(buffer[k]) && Number.isFinite(buffer[k + 1]) && Number.isFinite(buffer[k + 2])) {
      out[j++] = buffer[k];
      out[j++] = buffer[k + 1];
      out[j++] = buffer[k + 2];
    }
  }
  return out;
}

/**
 * The failing points of a preview by kind: {unsupported: {positions, count}, collisions: {...}}.
 * @throws Error for a buffer that is not whole xyz triples (pointCloud)
 */
export function failingPoints(preview) {
  const out = {};
  for (const f of FAILING_POINTS) {
    const positions = pointCloud(preview ? preview[f.buffer] : null, f.buffer);
    out[f.kind] = { positions, count: positions.length / 3 };
  }
  return out;
}

/** True when the preview carries failing points to draw. */
export function hasCheckPoints(preview) {
  return !!preview && FAILING_POINTS.some((f) => preview[f.buffer] && preview[f.buffer].length >= 3);
}

/**
 * The legend's count text of a kind of failing points: the points drawn, with the report's total
 * when the preview holds fewer (the core keeps at most 4000 of each, spread over all of them).
 */
export function pointCountText(drawn, total) {
  if (Number.isFinite(total) && total > drawn) return `${figure(drawn)} of ${figure(total)}`;
  return figure(drawn);
}

/**
 * RGBA pixels (size x size) of the points' sprite: a white disc in a dark ring, clear outside.
 * The material's colour tints the disc; the ring keeps a point legible on any tool-path colour.
 */
export function ringSprite(size = 32) {
  const px = new Uint8Array(size * size * 4);
  const c = (size - 1) / 2;
  for (let y = 0; y < size; y++) {
    for (let x = 0; x < size; x++) {
      const r = Math.hypot(x - c, y - c) / (size / 2);
      const k = 4 * (y * size + x);
      if (r > 1) continue;  // clear
      const v = r < 0.7 ? 255 : 16;
      px[k] = v;
      px[k + 1] = v;
      px[k + 2] = v;
      px[k + 3] = 255;
    }
  }
  return px;
}
