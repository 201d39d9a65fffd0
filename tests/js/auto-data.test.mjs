// SPDX-License-Identifier: MIT
// method = auto's page data (web/methods/auto-data.js) on a report of the documented shape
// (README "--method auto"): each candidate's state and cells, the choice's rows, the done line.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { autoDoneSummary, autoSection, autoSummaryRows, candidateRows, thumbnailLines } from '../../web/methods/auto-data.js';

const verify = (sound, supported, collisions, failures = []) => ({ sound, inside: 1, coverage: 0.7, supported, collisions, limits: 0, left_out_mm: 0, failures });
const report = {
  method: 'multidir',
  auto: {
    chosen: 'multidir',
    reason: 'multidir: sound, supported 0.990, 5 mm^3 of support, 0.39 h; over planar (170 mm^3 of support)',
    candidates: [
      { method: 'planar', status: 'ok', message: '', stopped_early: false, verify: verify(true, 0.997, 0), support_volume_mm3: 170.4, estimated_time_s: 1365, timings_ms: { total: 509 } },
      { method: 'multidir', status: 'ok', message: '', stopped_early: false, verify: verify(true, 0.990, 0), support_volume_mm3: 5, estimated_time_s: 1418, timings_ms: { total: 1439 } },
      { method: 'geodesic', status: 'dominated', message: 'stopped before its check: ...', stopped_early: true, verify: null, support_volume_mm3: 0, estimated_time_s: 4503, timings_ms: { total: 7431 } },
      { method: 'voxel', status: 'ok', message: '', stopped_early: false, verify: verify(false, 0.998, 17, ['17 samples collide']), support_volume_mm3: 0, estimated_time_s: 6907, timings_ms: { total: 11724 } },
      { method: 'surface', status: 'open_mesh', message: 'the mesh is closed', stopped_early: false, verify: null, support_volume_mm3: 0, estimated_time_s: 0, timings_ms: { total: 3 } },
    ],
  },
};

test('candidate rows: states, verdicts and figures in the order they ran', () => {
  const rows = candidateRows(autoSection(report));
  assert.deepEqual(rows.map((r) => [r.method, r.state]),
    [['planar', 'sound'], ['multidir', 'chosen'], ['geodesic', 'stopped'], ['voxel', 'unsound'], ['surface', 'failed']]);
  assert.equal(rows[0].support, '170 mm³');
  assert.equal(rows[0].supported, '0.997');
  assert.equal(rows[2].verdict, 'stopped: could not win');
  assert.equal(rows[2].supported, '—');
  assert.equal(rows[3].verdict, '17 samples collide');
  assert.equal(rows[3].collisions, '17');
  assert.equal(rows[4].verdict, 'the mesh is closed');
  assert.equal(rows[4].time, '—');
  assert.equal(rows[1].ms, '1.4 s');
});

test('the choice and the done line; nothing without an auto section', () => {
  const a = autoSection(report);
  assert.deepEqual(autoSummaryRows(a).map((r) => r[2]), ['multidir', report.auto.reason]);
  assert.equal(autoDoneSummary(a), 'auto chose multidir of 5');
  assert.equal(autoSection({ method: 'planar' }), null);
  assert.deepEqual(candidateRows(null), []);
  assert.equal(autoDoneSummary(null), '');
});

test('thumbnail: printed segments projected into the picture, travel left out, every k-th beyond the cap', () => {
  // A 10 x 10 x 10 mm cube's 12 edges printed (feature 1), one travel move far away, a collision
  // at a corner.
  const corners = [];
  for (const x of [0, 10]) for (const y of [0, 10]) for (const z of [0, 10]) corners.push([x, y, z]);
  const segs = [];
  for (let i = 0; i < 8; i++) {
    for (let j = i + 1; j < 8; j++) {
      const d = corners[i].map((v, k) => Math.abs(v - corners[j][k])).filter((v) => v > 0).length;
      if (d === 1) segs.push([...corners[i], ...corners[j]]);
    }
  }
  assert.equal(segs.length, 12);
  const positions = new Float32Array([...segs.flat(), 500, 500, 500, -500, -500, 0]);
  const features = new Uint8Array([...segs.map(() => 1), 0]);
  const collisionPoints = new Float32Array([10, 10, 10]);
  const t = thumbnailLines({ positions, features, collisionPoints }, 80, 60);
  assert.equal(t.features.length, 12);
  for (let i = 0; i < t.lines.length; i += 2) {
    assert.ok(t.lines[i] >= 1.999 && t.lines[i] <= 78.001, `x ${t.lines[i]}`);
    assert.ok(t.lines[i + 1] >= 1.999 && t.lines[i + 1] <= 58.001, `y ${t.lines[i + 1]}`);
  }
  // The top corner (10, 10, 10) is the highest point: the smallest y; it is where the collision is.
  const ys = [...t.lines].filter((_, i) => i % 2 === 1);
  assert.ok(Math.abs(t.collisions[1] - Math.min(...ys)) < 1e-3);
  assert.equal(t.unsupported.length, 0);
  // The cap: every k-th printed segment.
  assert.equal(thumbnailLines({ positions, features }, 80, 60, 4).features.length, 4);
  assert.equal(thumbnailLines({ positions: new Float32Array(6), features: new Uint8Array(1) }, 80, 60), null);
  assert.equal(thumbnailLines(null, 80, 60), null);
});
