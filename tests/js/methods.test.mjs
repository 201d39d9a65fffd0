// SPDX-License-Identifier: MIT
// The page's method registry (web/methods/index.js) in Node: every method module has the same
// shape {name, data, panel, view}; the registry's names are the settings' method choices and each
// method's settings group exists; each method's progress weights sum to 1 and overall progress
// only grows along them; report sections, done lines and machine hints come from the module of
// the section present; the planar module's general figures.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { METHODS, STAGE_WEIGHTS, doneSummary, machineHint, methodNamed, progressDetail } from '../../web/methods/index.js';
import { reportRows, warningNotes } from '../../web/methods/planar-data.js';
import { fieldsUnavailable, pageFields } from './page-settings.mjs';
import { newProgress, overallProgress, recordProgress, stageTimes } from '../../web/status-panel.js';

test('every method module has the registry\'s shape', () => {
  for (const m of METHODS) {
    assert.equal(typeof m.name, 'string');
    assert.deepEqual(Object.keys(m).sort(), ['data', 'name', 'panel', 'view'], m.name);
    for (const f of ['section', 'summaryRows', 'doneSummary', 'machineHint']) assert.equal(typeof m.data[f], 'function', `${m.name}.data.${f}`);
    assert.equal(typeof m.data.stageWeights, 'object', `${m.name}.data.stageWeights`);
    assert.equal(typeof m.data.settingsGroup, 'string', `${m.name}.data.settingsGroup`);
    for (const f of ['show', 'wire']) assert.equal(typeof m.panel[f], 'function', `${m.name}.panel.${f}`);
    assert.equal(typeof m.view.setup, 'function', `${m.name}.view.setup`);
    assert.equal(typeof m.view.build === 'function', typeof m.data.hasView === 'function', `${m.name}: build and hasView go together`);
    assert.equal(m.data.section(null), null, `${m.name}: no section without a report`);
    assert.ok(Array.isArray(m.data.summaryRows(null)), `${m.name}: rows without a section`);
    assert.equal(m.data.doneSummary(null), '', `${m.name}: no done line without a section`);
  }
});

test('the registry names the settings\' method choices; each method\'s settings group exists', { skip: fieldsUnavailable }, async () => {
  const fields = await pageFields();
  const options = fields.find((f) => f.key === 'method').options.map((o) => o.value);
  assert.deepEqual(METHODS.map((m) => m.name), options);
  const groups = new Set(fields.map((f) => f.group));
  for (const m of METHODS) assert.ok(groups.has(m.data.settingsGroup), `${m.name}: group ${m.data.settingsGroup}`);
  assert.equal(methodNamed('voxel').name, 'voxel');
  assert.equal(methodNamed('no-such-method').name, 'planar');
});

test('progress weights: each method\'s stages sum to 1 and overall progress only grows along them', () => {
  for (const [method, w] of Object.entries(STAGE_WEIGHTS)) {
    const sum = Object.values(w).reduce((a, b) => a + b, 0);
    assert.ok(Math.abs(sum - 1) < 1e-9, `${method}: ${sum}`);
    let last = 0;
    for (const stage of Object.keys(w)) {
      for (const f of [0, 0.25, 0.5, 1]) {
        const o = overallProgress(w, stage, f);
        assert.ok(o >= last - 1e-12, `${method} ${stage} ${f}`);
        last = o;
      }
    }
    assert.ok(Math.abs(last - 1) < 1e-9);
    assert.equal(overallProgress(w, 'no-such-stage', 0.5), null);
  }
  assert.deepEqual(Object.keys(STAGE_WEIGHTS.voxel).slice(3), ['voxelize', 'peeling', 'growth', 'layers', 'toolpath', 'motion', 'program']);
  // The surface method's stages as the engine reports them (the base's toolpath comes again for
  // the surface layer, after benchmark; the bar never goes back).
  assert.deepEqual(Object.keys(STAGE_WEIGHTS.surface),
    ['read', 'validate', 'place', 'slice', 'toolpath', 'feed', 'direction', 'paths', 'benchmark', 'motion', 'program']);
});

test('sections, done lines, progress details and machine hints come from the right module', () => {
  const voxel = { field_layers: 42, layers: 14, regions: 16, missed_voxels: 5 };
  assert.equal(methodNamed('voxel').data.section({ voxel }), voxel);
  assert.equal(methodNamed('surface').data.section({ isoplanar: { theta_deg: 3 } }).theta_deg, 3, 'the surface method draws report.isoplanar');
  assert.equal(methodNamed('geodesic').data.section({ voxel }), null);
  assert.equal(doneSummary({ voxel }), '42 field layers → 14 layers, 16 regions, 5 missed');
  assert.equal(doneSummary({ multidir: { part_count: 3, J_G_before: 12, J_G_after: 0.5 } }), '3 parts, J_G 12 → 0.5 mm²');
  assert.equal(doneSummary({ layers: 80 }), '', 'planar: no summary');
  assert.equal(progressDetail({ line: 'beam', level: 2, J_G: 1.25, beams: 8 }), 'search level 2: J_G = 1.25 mm² (beam, 8 beams)');
  assert.equal(progressDetail({}), '');
  assert.equal(machineHint('voxel', 'cartesian3'), 'the voxel method tilts the nozzle: choose table5, head4, head5 or a robot (cartesian3 has no tilt axes)');
  assert.equal(machineHint('surface', 'rotary4'),
    'the surface method keeps the nozzle along the surface normal: choose table5, head4, head5 or a robot (rotary4 has no tilt axes)');
  assert.equal(machineHint('geodesic', 'robot6'), '');
  assert.equal(machineHint('voxel', 'head5'), '', 'a 5-axis head tilts the nozzle');
  assert.equal(machineHint('multidir', 'head4'), '', 'a turning tilted nozzle');
  assert.equal(machineHint('multidir', 'cartesian3'),
    'the multidir method turns the part between parts: choose rotary4, table5, head4, head5 or a robot (cartesian3 has no rotary axis)');
  assert.equal(machineHint('multidir', 'rotary4'), '');
  assert.equal(machineHint('planar', 'cartesian3'), '');
});

test('planar: the report\'s general figures and warnings', () => {
  assert.deepEqual(reportRows(null).map(([key, , text]) => [key, text]), [
    ['layers', '—'], ['time', '—'], ['filament', '—'], ['path', '—'], ['supports', 'off'], ['took', '—'], ['machine', '—'], ['program', '—'],
  ]);
  const rows = Object.fromEntries(reportRows({
    layers: 85, estimated_time_s: 754, extrusion_mm: 1000, path_mm: 2500, timings_ms: { slice: 100, toolpath: 150 },
    machine: 'robot6-ur5', machine_kind: 'robot6', program_format: 'csv',
  }).map(([key, , text]) => [key, text]));
  assert.equal(rows.layers, '85');
  assert.equal(rows.time, '12 min 34 s');
  assert.equal(rows.filament, '1.00 m (3.0 g PLA)');
  assert.equal(rows.path, '2.50 m');
  assert.equal(rows.took, '0.25 s in the engine');
  assert.equal(rows.machine, 'robot6-ur5 (robot6)');
  assert.equal(rows.program, 'csv');
  // support = auto on planar layers says why.
  const auto = (chosen, pct) => Object.fromEntries(reportRows({ support_auto: { overhang_percent: pct, threshold_percent: 1,
    overhang_mm2: 10, chosen } }).map(([key, , text]) => [key, text])).supports;
  assert.equal(auto('none', 0.42), 'auto: 0.4 % of the surface overhangs, not above 1 % — off');
  assert.match(auto('projected', 7.86), /^auto: 7\.9 % of the surface overhangs, above 1 % — /);
  assert.deepEqual(warningNotes({ warnings: [{ code: 'skipped_tool_path', message: '3 mm left out' }, 'plain'] }),
    [{ code: 'skipped_tool_path', text: '3 mm left out' }, { code: '', text: 'plain' }]);
});

test('progress of method = auto in a pool: each candidate\'s stages are its own, side by side', () => {
  const p = newProgress({ auto: 1 });
  const events = [
    [0, { stage: 'auto', fraction: 0 }],
    [10, { stage: 'voxelize', fraction: 0.5, candidate: 'voxel' }],
    [20, { stage: 'field', fraction: 0.2, candidate: 'geodesic' }],
    [30, { stage: 'growth', fraction: 0.1, candidate: 'voxel' }],
    [40, { stage: 'field', fraction: 0.9, candidate: 'geodesic' }],
    [50, { stage: 'auto', fraction: 0.5 }],
  ];
  for (const [now, e] of events) recordProgress(p, e, { now });
  const times = new Map(stageTimes(p).map(([stage, e, ms]) => [stage, { fraction: e.fraction, ms }]));
  assert.deepEqual([...times.keys()], ['auto', 'voxel · voxelize', 'geodesic · field', 'voxel · growth']);
  // The voxel's first stage ended when its second began, not when the geodesic's began.
  assert.deepEqual(times.get('voxel · voxelize'), { fraction: 1, ms: 20 });
  assert.deepEqual(times.get('geodesic · field'), { fraction: 0.9, ms: 20 });
  assert.equal(times.get('voxel · growth').fraction, 0.1);
  assert.equal(p.overall, 0.5);
});
