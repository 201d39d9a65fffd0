// SPDX-License-Identifier: MIT
// How the page writes numbers: report figures, durations, lengths, percentages, lists of notes
// and the round values on chart axes. One module, so the report panels, the summaries and the
// charts of every method read alike ('—' wherever a figure is missing). Pure: Node tests load it.

/** A report figure: strings as they are; integers with thousands separators, other numbers to
 *  4 significant digits; '—' for anything else (missing, not finite). */
export function figure(x) {
  if (typeof x === 'string') return x;
  if (typeof x !== 'number' || !Number.isFinite(x)) return '—';
  return Number.isInteger(x) ? x.toLocaleString('en') : String(Number(x.toPrecision(4)));
}

/** `${format(x)} ${unit}` ('12.5 mm'), or '—' when x is not a finite number. */
export function withUnit(x, unit, format = figure) {
  return Number.isFinite(x) ? `${format(x)} ${unit}` : '—';
}

/** 'n things' ('1 thing'). */
export function plural(n, word) {
  return `${figure(n)} ${word}${n === 1 ? '' : 's'}`;
}

/** Seconds as 'h h mm min', 'm min ss s' or 's s'; '—' when not finite. */
export function formatSeconds(seconds) {
  if (!Number.isFinite(seconds)) return '—';
  const s = Math.round(seconds);
  const h = Math.floor(s / 3600);
  const m = Math.floor((s % 3600) / 60);
  return h > 0 ? `${h} h ${String(m).padStart(2, '0')} min` : m > 0 ? `${m} min ${String(s % 60).padStart(2, '0')} s` : `${s} s`;
}

/** A duration in milliseconds (the reports' timings_ms): '2.35 s' from a second on, else '412 ms'. */
export function formatMs(ms) {
  if (!Number.isFinite(ms)) return '—';
  return ms >= 1000 ? `${(ms / 1000).toFixed(2)} s` : `${Math.round(ms)} ms`;
}

/** A path length in mm: '123.4 mm', or '1.23 m' from a metre on; '—' when not finite. */
export function formatLength(mm) {
  if (!Number.isFinite(mm)) return '—';
  return mm >= 1000 ? `${(mm / 1000).toFixed(2)} m` : `${mm.toFixed(1)} mm`;
}

/** A short decimal text of x (mm): up to 3 significant digits, no trailing zeros. */
export function formatMm(x) {
  if (!Number.isFinite(x)) return '—';
  if (x === 0) return '0';
  const a = Math.abs(x);
  const digits = a >= 100 ? 0 : a >= 10 ? 1 : a >= 1 ? 2 : 3;
  return String(Number(x.toFixed(digits)));
}

/** A signed percentage text of a fraction ('+3.2 %', '−10.8 %', '0 %'), '' when not finite. */
export function percentText(fraction) {
  if (!Number.isFinite(fraction)) return '';
  const p = fraction * 100;
  if (Math.abs(p) < 0.05) return '0 %';
  return `${p > 0 ? '+' : '−'}${Math.abs(p).toFixed(1)} %`;
}

/**
 * A report's notes as lines of text: a list (strings, or objects with a message), or an object
 * of named flags and counts ({holes_filled: 2, flipped: true} -> 'holes_filled: 2', 'flipped';
 * zero and false entries left out), or one value; [] for null.
 */
export function describeList(value) {
  if (value == null) return [];
  if (Array.isArray(value)) return value.map((v) => (typeof v === 'string' ? v : v.message || JSON.stringify(v)));
  if (typeof value === 'object') {
    return Object.entries(value)
      .filter(([, v]) => v)
      .map(([k, v]) => (v === true ? k : `${k}: ${typeof v === 'object' ? JSON.stringify(v) : v}`));
  }
  return [String(value)];
}

/** Round tick values (1, 2 or 5 times a power of ten apart) in [lo, hi], about `count` of them. */
export function niceTicks(lo, hi, count = 4) {
  if (!(hi > lo) || !Number.isFinite(lo) || !Number.isFinite(hi)) return Number.isFinite(lo) ? [lo] : [];
  const rough = (hi - lo) / Math.max(count, 1);
  const p10 = 10 ** Math.floor(Math.log10(rough));
  const step = [1, 2, 5, 10].map((m) => m * p10).find((x) => x >= rough * 0.999) || 10 * p10;
  const out = [];
  for (let j = Math.ceil(lo / step - 1e-9); j * step <= hi + 1e-9 * step; j++) out.push(Number((j * step).toPrecision(12)));
  return out;
}
