// SPDX-License-Identifier: MIT
// The multidir page's pure data (web/methods/multidir-data.js) in Node: buffer checks, parts sorted by
// print index with one colour each, centroids and direction arrows, risky-face index lists and
// areas, the J_G-per-level chart, the report's rows, the search-level progress text and the live
// chart's values.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import {
  areaFigure, arrowSegments, checkMultidirBuffers, flaggedArea, flaggedTriangles, hasMultidirBuffers, jgChartGeometry, liveJgLevels,
  multidirDoneSummary, multidirSummaryRows, partCentroids, partColor, partDirections, partRows, searchLevelText, sortPartTriangles,
  supportText,
} from '../../web/methods/multidir-data.js';

// Two unit-square "parts" (two triangles each): part 1 listed first at z = 5, part 0 at z = 0.
function makePreview() {
  return {
    partPositions: new Float32Array([0, 0, 5, 1, 0, 5, 1, 1, 5, 0, 1, 5, 0, 0, 0, 2, 0, 0, 2, 2, 0, 0, 2, 0]),
    partTriangles: new Uint32Array([0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7]),
    partIds: new Uint32Array([1, 1, 0, 0]),
    riskyBefore: new Uint8Array([1, 1, 0, 0]),
    riskyAfter: new Uint8Array([0, 1, 0, 0]),
  };
}
const REPORT = {
  J_G_before: 200, J_G_after: 0, ratio: 0, alpha_max_deg: 45, scheme: 'beam', dof: '5dof', rotation_axis: null,
  parts: [
    { print_index: 0, direction: [0, 0, 1], plane: null, volume_mm3: 3000, components: 1, risky_area_mm2: 0, layers: 100 },
    { print_index: 1, direction: [1, 0, 0], plane: { normal: [1, 0, 0], offset_mm: 10 }, volume_mm3: 2000, components: 1, risky_area_mm2: 0, layers: 67 },
  ],
  part_count: 2, volume_mm3: 5000, cap_area_mm2: 100,
  search: { levels: 3, beams: 8, restarts_run: 2, perturbations: 60, perturbations_kept: 3, candidates_evaluated: 1234, J_G_per_level: [200, 0, 0] },
  timings_ms: { search: 12, clip: 3 },
};

test('checkMultidirBuffers: sizes, indices, flags per mesh triangle', () => {
  const p = makePreview();
  assert.ok(hasMultidirBuffers(p));
  assert.ok(!hasMultidirBuffers({ partIds: new Uint32Array(0) }));
  assert.deepEqual(checkMultidirBuffers(p, 4), { vertices: 8, triangles: 4, parts: 2, meshTriangles: 4 });
  assert.throws(() => checkMultidirBuffers(p, 5), /4 risky flags for a mesh of 5 triangles/);
  assert.throws(() => checkMultidirBuffers({ ...p, partIds: new Uint32Array([0]) }), /1 part ids for 4 triangles/);
  assert.throws(() => checkMultidirBuffers({ ...p, partTriangles: new Uint32Array([0, 1, 9]), partIds: new Uint32Array([0]) }), /uses vertex 9 of 8/);
  assert.throws(() => checkMultidirBuffers({ ...p, riskyAfter: new Uint8Array(3) }), /4 risky-before flags and 3/);
  assert.throws(() => checkMultidirBuffers({ ...p, partPositions: new Float32Array([0, 0]) }), /not 3 per vertex/);
});

test('sortPartTriangles: by print index, stable, one colour per part', () => {
  const s = sortPartTriangles(makePreview());
  assert.equal(s.parts, 2);
  assert.deepEqual([...s.starts], [0, 2, 4]);
  // Part 0 (z = 0) first.
  for (let k = 0; k < 6; k++) assert.equal(s.positions[3 * k + 2], 0);
  for (let k = 6; k < 12; k++) assert.equal(s.positions[3 * k + 2], 5);
  assert.deepEqual([...s.colors.slice(0, 3)], partColor(0));
  assert.deepEqual([...s.colors.slice(18, 21)], partColor(1));
  assert.notDeepEqual(partColor(0), partColor(1));
  // Neighbouring parts differ clearly in hue.
  for (let i = 0; i < 12; i++) {
    const a = partColor(i);
    const b = partColor(i + 1);
    assert.ok(Math.abs(a[0] - b[0]) + Math.abs(a[1] - b[1]) + Math.abs(a[2] - b[2]) > 60, `parts ${i}, ${i + 1}`);
  }
});

test('partCentroids, partDirections, arrowSegments', () => {
  const p = makePreview();
  const c = partCentroids(p, 3);
  assert.deepEqual([...c.slice(0, 3)].map((x) => Number(x.toFixed(6))), [1, 1, 0]);
  assert.deepEqual([...c.slice(3, 6)].map((x) => Number(x.toFixed(6))), [0.5, 0.5, 5]);
  assert.ok(Number.isNaN(c[6]), 'a part without triangles has no centroid');
  const d = partDirections(REPORT, 3);
  assert.deepEqual([...d], [0, 0, 1, 1, 0, 0, 0, 0, 1]);
  const a = arrowSegments(c, d, 4);
  assert.equal(a.length, 3 * 18);
  // Part 1: shaft from (0.5, 0.5, 5) to (4.5, 0.5, 5), head strokes end 1 mm back along -X.
  assert.deepEqual([...a.slice(18, 24)], [0.5, 0.5, 5, 4.5, 0.5, 5]);
  assert.equal(a[24], 4.5);
  assert.ok(Math.abs(a[27] - 3.5) < 1e-6 && Math.abs(a[33] - 3.5) < 1e-6);
  assert.ok(a.slice(36).every((x) => x === 0), 'no arrow without a centroid');
});

test('flaggedTriangles and flaggedArea', () => {
  const positions = new Float32Array([0, 0, 0, 2, 0, 0, 0, 2, 0, 0, 0, 3]);
  const indices = new Uint32Array([0, 1, 2, 0, 1, 3, 0, 2, 3]);
  assert.deepEqual([...flaggedTriangles(indices, new Uint8Array([1, 0, 1]))], [0, 1, 2, 0, 2, 3]);
  assert.equal(flaggedArea(positions, indices, new Uint8Array([1, 0, 1])), 2 + 3);
  assert.equal(flaggedArea(positions, indices, new Uint8Array(3)), 0);
});

test('jgChartGeometry: a point per level, y from 0 to the largest J_G', () => {
  const c = jgChartGeometry([200, 50, 0], { width: 260, height: 110 });
  assert.equal(c.points.length, 3);
  assert.equal(c.maxValue, 200);
  assert.equal(c.points[0].y, c.plot.y, 'the largest value at the top');
  assert.equal(c.points[2].y, c.plot.y + c.plot.height, 'zero at the bottom');
  assert.ok(c.points[0].x < c.points[1].x && c.points[1].x < c.points[2].x);
  assert.match(c.path, /^M[\d.]+,[\d.]+ L/);
  assert.ok(c.yTicks.some((t) => t.value === 0) && c.yTicks.every((t) => t.value <= 200));
  assert.deepEqual(c.xTicks.map((t) => t.value), [0, 1, 2]);
  assert.equal(jgChartGeometry([]).points.length, 0);
  assert.throws(() => jgChartGeometry([1, NaN]), /level 1/);
});

test('summary rows, parts table, done summary', () => {
  const rows = Object.fromEntries(multidirSummaryRows(REPORT).map(([k, , t]) => [k, t]));
  assert.equal(rows.jg, '200 mm² → 0 mm² (0 %)');
  assert.equal(rows.parts, '2');
  assert.match(rows.search, /^beam, 5dof, α_max 45 °/);
  assert.equal(rows.candidates, '1,234');
  assert.equal(rows.levels, '3, 8, 2');
  assert.equal(rows.moves, '3 of 60');
  const parts = partRows(REPORT);
  assert.equal(parts.length, 2);
  assert.deepEqual(parts.map((r) => [r.index, r.platform, r.layers]), [[0, true, 100], [1, false, 67]]);
  assert.equal(parts[1].direction, '(1.000, 0, 0)');
  assert.equal(Math.round(parts[1].tiltDeg), 90);
  assert.equal(multidirDoneSummary(REPORT), '2 parts, J_G 200 → 0 mm²');
  assert.equal(multidirDoneSummary(null), '');
  assert.equal(multidirDoneSummary({ ...REPORT, J_G_after: 3e-9 }), '2 parts, J_G 200 → 0 mm²', 'rounding noise shows as 0');
  assert.equal(areaFigure(1234.567), '1235');
  assert.equal(areaFigure(12.345), '12.35');
  assert.deepEqual(partRows(null), []);
  assert.equal(rows.supports, 'off');
});

test('supports line: off unless generated, counts and printed volume when they are', () => {
  assert.equal(supportText(undefined), 'off');
  assert.equal(supportText({ generated: false }), 'off');
  const sup = { generated: true, printed_volume_mm3: 64.024, struts: 50, samples: 50, landed_on_platform: 41,
    landed_on_model: 7, blocked: 2, roofs: 244 };
  assert.equal(supportText(sup), '64 mm³ printed: 50 struts from 50 overhang samples (41 to the platform, 7 on the part, 2 blocked), 244 roof faces');
  assert.doesNotMatch(supportText({ ...sup, blocked: 0 }), /blocked/);
  const rows = Object.fromEntries(multidirSummaryRows({ ...REPORT, supports: sup }).map(([k, , t]) => [k, t]));
  assert.match(rows.supports, /^64 mm³ printed: 50 struts/);
  assert.deepEqual(partRows({ parts: [{ print_index: 0, plane: null, support_region_mm3: 12.5 }] }).map((r) => r.support), [12.5]);
});

test('searchLevelText: level, J_G to 0.01 mm², the line and its live beams', () => {
  assert.equal(searchLevelText({ line: 'beam', level: 3, J_G: 1.2345, beams: 8 }), 'search level 3: J_G = 1.23 mm² (beam, 8 beams)');
  assert.equal(searchLevelText({ line: 'greedy', level: 1, J_G: 50, beams: 1 }), 'search level 1: J_G = 50 mm² (greedy, 1 beam)');
  assert.equal(searchLevelText({ line: 'constrained', level: 4, J_G: 2e-9, beams: 0 }), 'search level 4: J_G = 0 mm² (constrained)');
  assert.equal(searchLevelText({ line: 'chosen', level: 2, J_G: 0.0312, beams: 0 }), 'search level 2: J_G = 0.03 mm² (chosen)');
  for (const bad of [undefined, null, {}, { line: 'beam', level: -1, J_G: 1 }, { line: 'beam', level: 1.5, J_G: 1 },
    { line: 'beam', level: 1, J_G: NaN }, { line: '', level: 1, J_G: 1 }]) {
    assert.equal(searchLevelText(bad), '', JSON.stringify(bad));
  }
});

test('liveJgLevels: least J_G with at most k planes over the search lines, then the chosen sequence', () => {
  const ev = (line, level, J_G, beams = 1) => ({ line, level, J_G, beams });
  assert.deepEqual(liveJgLevels([]), []);
  assert.deepEqual(liveJgLevels(null), []);
  // The greedy line alone: its values.
  const greedy = [ev('greedy', 0, 200), ev('greedy', 1, 120), ev('greedy', 2, 40), ev('greedy', 3, 40, 0)];
  assert.deepEqual(liveJgLevels(greedy), [200, 120, 40, 40]);
  // The beam, two levels in, is better at level 1 and reaches 10 at level 2: levels 2-3 follow it
  // (at most k planes), the chart never rises.
  const withBeam = [...greedy, ev('constrained', 0, 200), ev('constrained', 1, 150), ev('beam', 0, 200, 1), ev('beam', 1, 60, 8), ev('beam', 2, 10, 8)];
  assert.deepEqual(liveJgLevels(withBeam), [200, 60, 10, 10]);
  // The axis screening (coarse grid) is left out.
  assert.deepEqual(liveJgLevels([ev('screen', 0, 200), ev('screen', 1, 1)]), []);
  assert.deepEqual(liveJgLevels([...greedy, ev('screen', 1, 1)]), [200, 120, 40, 40]);
  // The chosen sequence replaces the search's values: exactly its levels.
  const chosen = [...withBeam, ev('chosen', 0, 200, 0), ev('chosen', 1, 61, 0), ev('chosen', 2, 8.5, 0)];
  assert.deepEqual(liveJgLevels(chosen), [200, 61, 8.5]);
  // Half of a chosen sequence so far: the levels that came.
  assert.deepEqual(liveJgLevels(chosen.slice(0, -1)), [200, 61]);
  // Malformed events are skipped.
  assert.deepEqual(liveJgLevels([...greedy, { line: 'beam', level: 1, J_G: -3 }, { line: 'beam' }]), [200, 120, 40, 40]);
});
