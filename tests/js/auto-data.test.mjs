// SPDX-License-Identifier: MIT
// method = auto's page data (web/methods/auto-data.js) on a report of the documented shape
// (README "--method auto"): each candidate's state and cells, the choice's rows, the done line.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { autoDoneSummary, autoSection, autoSummaryRows, candidateRows } from '../../web/methods/auto-data.js';

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
