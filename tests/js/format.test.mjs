// SPDX-License-Identifier: MIT
// The page's formatting helpers (web/format.js) in Node: figures, units, durations, lengths,
// notes and chart ticks as the panels show them.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import {
  describeList, figure, formatLength, formatMm, formatMs, formatSeconds, niceTicks, percentText, plural, withUnit,
} from '../../web/format.js';

test('figures: integers with separators, others to 4 significant digits, strings as they are, else a dash', () => {
  assert.equal(figure(1234567), '1,234,567');
  assert.equal(figure(3.14159), '3.142');
  assert.equal(figure('A3'), 'A3');
  for (const x of [NaN, Infinity, null, undefined, true]) assert.equal(figure(x), '—');
  assert.equal(withUnit(12.5, 'mm'), '12.5 mm');
  assert.equal(withUnit(NaN, 'mm'), '—');
  assert.equal(withUnit(0.12345, 'mm', formatMm), '0.123 mm');
  assert.equal(plural(1, 'edge'), '1 edge');
  assert.equal(plural(2000, 'edge'), '2,000 edges');
  assert.equal(percentText(-0.108), '−10.8 %');
});

test('durations and lengths', () => {
  assert.equal(formatSeconds(42.4), '42 s');
  assert.equal(formatSeconds(754), '12 min 34 s');
  assert.equal(formatSeconds(3 * 3600 + 5 * 60), '3 h 05 min');
  assert.equal(formatSeconds(NaN), '—');
  assert.equal(formatMs(412.4), '412 ms');
  assert.equal(formatMs(2345), '2.35 s');
  assert.equal(formatMs(undefined), '—');
  assert.equal(formatLength(123.44), '123.4 mm');
  assert.equal(formatLength(1234), '1.23 m');
  assert.equal(formatMm(0), '0');
  assert.equal(formatMm(12.345), '12.3');
  assert.equal(formatMm(123.4), '123');
});

test('notes: lists, flag objects and single values as lines', () => {
  assert.deepEqual(describeList(null), []);
  assert.deepEqual(describeList(['a', { message: 'b' }, { code: 'c' }]), ['a', 'b', '{"code":"c"}']);
  assert.deepEqual(describeList({ holes_filled: 2, flipped: true, merged: 0, none: false, box: { a: 1 } }),
    ['holes_filled: 2', 'flipped', 'box: {"a":1}']);
  assert.deepEqual(describeList(7), ['7']);
});

test('chart ticks: round values 1, 2 or 5 times a power of ten apart', () => {
  assert.deepEqual(niceTicks(0, 10, 4), [0, 5, 10]);
  assert.deepEqual(niceTicks(-0.12, 0.12, 4), [-0.1, 0, 0.1]);
  assert.deepEqual(niceTicks(0.3, 0.9, 6), [0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9]);
  assert.deepEqual(niceTicks(5, 5), [5]);
});
