// SPDX-License-Identifier: MIT
// The settings model of the page (web/settings-panel.js) in Node: what a slice request carries
// (placement keys always, other keys only when changed, machine_json only when a profile is
// loaded), the machine kind the panel shows rows for, and the machine_json field's checks.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import {
  PLACEMENT_KEYS, SETTINGS_SCHEMA, SetSettingCommand, SettingsModel, normaliseValue, selectedMachineKind,
} from '../../web/settings-panel.js';

test('slice settings: placement keys always, others only when changed from the defaults', () => {
  const model = new SettingsModel();
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
    SETTINGS_SCHEMA.filter((f) => f.key !== 'machine_json').map((f) => f.key).sort());
});

test('machine_json: one-line JSON object text; undoable; it decides the machine kind', () => {
  const model = new SettingsModel();
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
  const showIf = (key) => SETTINGS_SCHEMA.find((f) => f.key === key).showIf(model.values);
  assert.equal(showIf('robot_format'), false);
  assert.equal(showIf('gcode_flavor'), true);
  command.undo();
  assert.equal(model.get('machine_json'), '');
  assert.equal(showIf('robot_format'), true);
  assert.equal(showIf('gcode_flavor'), false);
});
