// SPDX-License-Identifier: MIT
// The settings fields and model of the page (web/settings-fields.js, web/settings-panel.js) in
// Node: what a slice request carries (placement keys always, other keys only when changed,
// machine_json only when a profile is loaded), the machine kind the panel shows rows for, the
// machine_json field's checks, and the placement keys (web/placement.js). The fields are built
// over the core's settings table, as the page does (page-settings.mjs).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { PAGE_FIELDS, selectedMachineKind, settingsFields, usesIsoplanar } from '../../web/settings-fields.js';
import { SetSettingCommand, SettingsModel, normaliseValue } from '../../web/settings-panel.js';
import { PLACEMENT_KEYS, isPlacementKey, placementOf } from '../../web/placement.js';
import { coreSettingsSchema, fieldsUnavailable, pageFields } from './page-settings.mjs';

const FIELDS = fieldsUnavailable ? [] : await pageFields();
const needsFields = { skip: fieldsUnavailable };

test('slice settings: placement keys always, others only when changed from the defaults', needsFields, () => {
  const model = new SettingsModel(FIELDS);
  assert.deepEqual(Object.keys(model.toSliceSettings()).sort(), [...PLACEMENT_KEYS].sort());
  model.set('machine', 'robot6-ur5');
  model.set('robot_format', 'urscript');
  model.set('infill', 35);
  const s = model.toSliceSettings();
  assert.equal(s.machine, 'robot6-ur5');
  assert.equal(s.robot_format, 'urscript');
  assert.equal(s.infill, 35);
  assert.equal('gcode_flavor' in s, false);
  assert.equal('machine_json' in s, false);
  model.set('infill', 20);
  assert.equal('infill' in model.toSliceSettings(), false, 'back at the default');
  // Every key is in toSettings (the page's view of the settings), machine_json only when set.
  assert.deepEqual(Object.keys(model.toSettings()).sort(),
    FIELDS.filter((f) => f.key !== 'machine_json').map((f) => f.key).sort());
});

test('machine_json: one-line JSON object text; undoable; it decides the machine kind', needsFields, () => {
  const model = new SettingsModel(FIELDS);
  const field = model.field('machine_json');
  assert.equal(normaliseValue(field, ''), '');
  assert.equal(normaliseValue(field, '{\n  "kind": "table5"\n}'), '{"kind":"table5"}', 'made one line');
  assert.throws(() => normaliseValue(field, '{"kind": '), /not JSON/);
  assert.throws(() => normaliseValue(field, '[1, 2]'), /not a JSON object/);
  assert.equal(selectedMachineKind(model.values), 'cartesian3');
  model.set('machine', 'robot6-ur5');
  assert.equal(selectedMachineKind(model.values), 'robot6');
  const command = new SetSettingCommand(model, 'machine_json', '{"kind":"rotary4","pivot":[0,0,0]}');
  command.execute();
  assert.equal(selectedMachineKind(model.values), 'rotary4', 'a loaded profile overrides the select');
  assert.equal(model.toSliceSettings().machine_json, '{"kind":"rotary4","pivot":[0,0,0]}');
  // showIf rows: the robot format only for robots, the flavour only for G-code machines.
  const showIf = (key) => FIELDS.find((f) => f.key === key).showIf(model.values);
  assert.equal(showIf('robot_format'), false);
  assert.equal(showIf('gcode_flavor'), true);
  command.undo();
  assert.equal(model.get('machine_json'), '');
  assert.equal(showIf('robot_format'), true);
  assert.equal(showIf('gcode_flavor'), false);
});

test('axis_letters and thumbnails: one line of text, sent when set, rows for G-code machines only', needsFields, () => {
  const model = new SettingsModel(FIELDS);
  for (const key of ['axis_letters', 'thumbnails']) {
    assert.equal(model.field(key).type, 'text');
    assert.equal(model.field(key).value, '', 'none by default');
  }
  const field = model.field('axis_letters');
  assert.equal(field.type, 'text');
  assert.equal(field.value, '', "the core's default: the profile's letters");
  assert.equal(normaliseValue(field, '  B=U,C=V '), 'B=U,C=V');
  assert.equal(normaliseValue(field, null), '');
  assert.throws(() => normaliseValue(field, 'B=U\nC=V'), /one line/);
  assert.equal('axis_letters' in model.toSliceSettings(), false);
  const command = new SetSettingCommand(model, 'axis_letters', 'B=U,C=V');
  command.execute();
  assert.equal(model.toSliceSettings().axis_letters, 'B=U,C=V');
  command.undo();
  assert.equal('axis_letters' in model.toSliceSettings(), false);
  const showIf = () => field.showIf(model.values);
  model.set('machine', 'table5');
  assert.equal(showIf(), true);
  assert.equal(model.field('thumbnails').showIf(model.values), true);
  model.set('machine', 'robot6-ur5');
  assert.equal(showIf(), false, 'a robot program has joints, not letters');
  assert.equal(model.field('thumbnails').showIf(model.values), false, 'robot programs have no printer host');
});

test('iso-planar settings: shown and sent only with the surface method or the iso-planar fill', needsFields, () => {
  const model = new SettingsModel(FIELDS);
  const showIf = (key) => FIELDS.find((f) => f.key === key).showIf(model.values);
  const isoKeys = ['isoplanar.theta_deg', 'isoplanar.directions', 'isoplanar.chord_error_mm', 'isoplanar.benchmark'];
  assert.equal(usesIsoplanar(model.values), false);
  for (const key of [...isoKeys, 'surface.base_mm']) assert.equal(showIf(key), false, `${key} hidden for planar/auto`);
  model.set('isoplanar.theta_deg', 30);
  model.set('isoplanar.chord_error_mm', 0.2);
  assert.equal('isoplanar.theta_deg' in model.toSliceSettings(), false, 'not sent while the fill does not use it');
  model.set('fill', 'isoplanar');
  for (const key of isoKeys) assert.equal(showIf(key), true, `${key} shown for fill = isoplanar`);
  assert.equal(showIf('surface.base_mm'), false, 'the base belongs to the surface method');
  let s = model.toSliceSettings();
  assert.equal(s.fill, 'isoplanar');
  assert.equal(s['isoplanar.theta_deg'], 30);
  assert.equal(s['isoplanar.chord_error_mm'], 0.2);
  assert.equal('isoplanar.directions' in s, false, 'defaults are left to the core');
  model.set('fill', 'auto');
  model.set('method', 'surface');
  model.set('surface.base_mm', 3);
  s = model.toSliceSettings();
  assert.equal(s.method, 'surface');
  assert.equal(s['isoplanar.theta_deg'], 30, 'the surface method prints iso-planar paths');
  assert.equal(s['surface.base_mm'], 3);
  assert.equal(showIf('surface.base_mm'), true);
  // The direction: -1 (search) or a forced angle in [0, 180). The panel checks the core table's
  // closed range -1..180; the core itself refuses 180 when it reads the settings (validateSettings, core/pipeline/settings.cpp).
  const theta = model.field('isoplanar.theta_deg');
  assert.equal(normaliseValue(theta, '-1'), -1);
  assert.equal(normaliseValue(theta, '158'), 158);
  assert.throws(() => normaliseValue(theta, '180.5'), /within -1..180/);
  assert.throws(() => normaliseValue(model.field('isoplanar.directions'), '1.5'), /whole number/);
});

test('placement keys: named once (web/placement.js), the settings\' Placement group, what a load carries', needsFields, () => {
  assert.deepEqual(FIELDS.filter((f) => f.group === 'Placement').map((f) => f.key).sort(), [...PLACEMENT_KEYS].sort());
  assert.equal(isPlacementKey('fit_mm'), true);
  assert.equal(isPlacementKey('layer_height'), false);
  const model = new SettingsModel(FIELDS);
  model.set('fit_mm', 60);
  assert.deepEqual(Object.keys(model.toPlacement()), [...PLACEMENT_KEYS]);
  assert.equal(model.toPlacement().fit_mm, 60);
  assert.deepEqual(placementOf({ up: 'y', layer_height: 0.3, center: false }), { up: 'y', center: false });
});

test('settingsFields: the page keeps no defaults, ranges or choices; drift from the core table throws naming the key', needsFields, async () => {
  const schema = await coreSettingsSchema();
  for (const f of PAGE_FIELDS) {
    for (const k of ['value', 'min', 'max', 'options', 'choices']) assert.equal(k in f, false, `${f.key}: ${k} comes from the core`);
  }
  // The built fields: the core's numbers, the page's parts kept, the alias mapped but not renamed.
  const nozzle = FIELDS.find((f) => f.key === 'nozzle');
  const core = schema.find((s) => s.key === 'nozzle_diameter');
  assert.deepEqual([nozzle.value, nozzle.min, nozzle.max, nozzle.help], [Number(core.default), core.min, core.max, core.help]);
  assert.equal('core' in nozzle, false);
  assert.equal(FIELDS.find((f) => f.key === 'voxel.smooth').type, 'integer', 'whole numbers of a core number');
  assert.equal(FIELDS.find((f) => f.key === 'walls').type, 'integer', 'the core\'s integer');
  const without = (key) => schema.filter((s) => s.key !== key);
  const withEntry = (key, change) => schema.map((s) => (s.key === key ? { ...s, ...change } : s));
  assert.throws(() => settingsFields(without('walls')), /settings field 'walls': it is not in the core's settings table/);
  assert.throws(() => settingsFields(without('nozzle_diameter')), /'nozzle': its core key 'nozzle_diameter'/);
  assert.throws(() => settingsFields(withEntry('walls', { type: 'choice' })), /'walls': the core's choice setting needs a page input type/);
  assert.throws(() => settingsFields(withEntry('center', { type: 'number' })), /'center': a checkbox input cannot edit the core's number/);
  assert.throws(() => settingsFields(withEntry('infill_pattern', { choices: ['grid'] })), /'infill_pattern'.*'lines'/);
  assert.throws(() => settingsFields(withEntry('voxel.smooth', { default: '2.5' })), /'voxel.smooth'.*whole number/);
  // Choices in the page's label order; one the page has no label for shows as itself, last.
  const pattern = settingsFields(withEntry('infill_pattern', { choices: ['lines', 'grid', 'gyroid'] }))
    .find((f) => f.key === 'infill_pattern');
  assert.deepEqual(pattern.options, [{ label: 'grid', value: 'grid' }, { label: 'lines', value: 'lines' }, { label: 'gyroid', value: 'gyroid' }]);
});

test('supports: offered and sent for every method (curved layers: fins), the planar-only details not', needsFields, () => {
  const model = new SettingsModel(FIELDS);
  const field = (key) => FIELDS.find((f) => f.key === key);
  for (const method of ['planar', 'multidir', 'voxel', 'geodesic']) {
    model.set('method', method);
    model.set('support', 'projected');
    assert.notEqual(field('support').showIf?.(model.values), false, `${method}: the supports row is shown`);
    assert.equal(model.toSliceSettings().support, 'projected', `${method}: the choice is sent`);
    const curved = method === 'voxel' || method === 'geodesic';
    assert.equal(field('support.sampling_mm').showIf(model.values), !curved, `${method}: sampling row`);
  }
});
