// SPDX-License-Identifier: MIT
// Pure data of the planar method's page, which is also what every result shows (each method's
// program is made of tool-path layers and reported with these figures): the progress stages, the
// report's general figures (layers, time, filament, path, supports, engine time, machine,
// program) and its warnings. No three.js, no DOM; unit-tested in Node.
import { describeList, formatLength, formatSeconds } from '../format.js';
import { supportText } from './multidir-data.js';

/**
 * Progress stages of a planar slice, in pipeline order, with their share of the bar (sums to 1).
 * feed, direction: the drive direction theta* of fill = isoplanar (absent otherwise: the bar
 * skips their small share).
 */
export const PLANAR_STAGE_WEIGHTS = Object.freeze({
  read: 0.04, validate: 0.06, place: 0.02, slice: 0.28, feed: 0.03, direction: 0.02, toolpath: 0.4, program: 0.15,
});

// Filament shown in grams: 1.75 mm PLA.
const FILAMENT_AREA_MM2 = Math.PI * (1.75 / 2) ** 2;
const PLA_G_PER_MM3 = 1.24e-3;

/**
 * Rows [key, label, text] of a slice report's general figures, in display order (keys double as
 * data-testid suffixes: report-<key>); null or absent figures show '—'.
 */
export function reportRows(report) {
  const r = report || {};
  const filament = Number.isFinite(r.extrusion_mm)
    ? `${formatLength(r.extrusion_mm)} (${(r.extrusion_mm * FILAMENT_AREA_MM2 * PLA_G_PER_MM3).toFixed(1)} g PLA)` : '—';
  const t = r.timings_ms && typeof r.timings_ms === 'object' ? r.timings_ms : null;
  const total = t && (Number.isFinite(t.total) ? t.total
    : Object.values(t).filter(Number.isFinite).reduce((a, b) => a + b, 0));
  return [
    ['layers', 'layers', r.layers !== undefined ? String(r.layers) : '—'],
    ['time', 'print time', formatSeconds(r.estimated_time_s)],
    ['filament', 'filament', filament],
    ['path', 'path length', formatLength(r.path_mm)],
    // Projected supports: the planar report's `support`, or the multidir report's `supports`;
    // with support = auto on planar layers, why auto chose them (report.support_auto).
    ['supports', 'supports', autoSupportText(r.support_auto, supportText(r.support || (r.multidir && r.multidir.supports)))],
    ['took', 'slicing took', t ? `${(total / 1000).toFixed(2)} s in the engine` : '—'],
    ['machine', 'machine', r.machine ? `${r.machine}${r.machine_kind && r.machine_kind !== r.machine ? ` (${r.machine_kind})` : ''}` : '—'],
    ['program', 'program', r.program_format || r.program_extension || '—'],
  ];
}

/** support = auto (planar): the overhanging share and the threshold before what was chosen. */
export function autoSupportText(auto, text) {
  if (!auto || !Number.isFinite(auto.overhang_percent)) return text;
  const chose = auto.chosen === 'projected' ? 'above' : 'not above';
  return `auto: ${auto.overhang_percent.toFixed(1)} % of the surface overhangs, ${chose} ${auto.threshold_percent} % — ${text}`;
}

/** What the user should know about a result (e.g. tool path left out): [{code, text}]. */
export function warningNotes(report) {
  const list = report && Array.isArray(report.warnings) ? report.warnings : [];
  return list.map((w) => ({ code: w && w.code ? String(w.code) : '', text: describeList([w])[0] }));
}
