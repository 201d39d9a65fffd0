// SPDX-License-Identifier: MIT
// The G-code side of the CuraEngine comparison (scripts/cura-compare.mjs, issue 7 bench): support
// and model volumes from ;TYPE: sections with absolute and relative E, G92 resets and retractions.
// Synthetic G-code only: CuraEngine is not needed.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { curaSettings, parseCuraGcode } from '../../scripts/cura-compare.mjs';

// A filament whose cross-section is 1 mm^2, so volumes equal filament lengths.
const UNIT = { filamentDiameterMm: 2 / Math.sqrt(Math.PI) };
const close = (a, b, what) => assert.ok(Math.abs(a - b) < 1e-9, `${what}: ${a} != ${b}`);

const GCODE = `;FLAVOR:Marlin
;TIME:6666
;Filament used: 0m
;LAYER_COUNT:2
M82 ;absolute extrusion mode
G92 E0
G1 F200 E3 ; start G-code prime: before any ;TYPE:, not counted
G92 E0
;LAYER:0
;TYPE:WALL-OUTER
G0 X0 Y0 Z0.4
G1 X10 Y0 E1.0
G1 X10 Y10 E2.0
G1 F2700 E-4.5 ; retraction of 6.5
G0 X20 Y0
G1 F2700 E2.0 ; prime: repays the retraction, no extrusion
;TYPE:SUPPORT
G1 X20 Y5 E2.5
G92 E0
G1 X20 Y10 E0.5
;LAYER:1
;TYPE:SUPPORT-INTERFACE
M83 ;relative extrusion mode
G1 X25 Y10 E0.25
G1 E-1
G0 X30 Y10
G1 E1
G1 X30 Y13 Z0.8 E0.3 ; a comment E99
;TYPE:FILL
G1 X40 Y13 E0.75
G1 E-2
G1 E1.5 ; partial prime
G1 X40 Y20 E1.0 ; repays the last 0.5 first
;TIME_ELAPSED:123.5
M82
G92 E1
G1 E-1 F300 ; end G-code retraction
`;

test('support and model volumes: absolute/relative E, G92 resets, retractions and primes', () => {
  const r = parseCuraGcode(GCODE, UNIT);
  close(r.by_type_mm3['WALL-OUTER'], 2, 'wall');
  close(r.by_type_mm3.SUPPORT, 1, 'support');
  close(r.by_type_mm3['SUPPORT-INTERFACE'], 0.55, 'support interface');
  close(r.by_type_mm3.FILL, 1.25, 'fill');
  close(r.support_volume_mm3, 1.55, 'support volume');
  close(r.model_volume_mm3, 3.25, 'model volume');
  close(r.total_volume_mm3, 4.8, 'total volume');
  close(r.filament_mm, 4.8, 'filament');
  close(r.support_path_mm, 15 + Math.hypot(3, 0.4), 'support path');
  assert.equal(r.layers, 2);
  // The header's ;TIME: is CuraEngine's placeholder: the last ;TIME_ELAPSED is used.
  assert.equal(r.print_time_s, 123.5);
  assert.equal(r.print_time_source, 'last ;TIME_ELAPSED');
});

test('volumes scale with the filament cross-section (1.75 mm by default)', () => {
  const r = parseCuraGcode(GCODE);
  close(r.support_volume_mm3, 1.55 * Math.PI * 0.875 ** 2, 'support volume');
  close(r.filament_mm, 4.8, 'filament');
});

test('print time: the engine log header first, then a real G-code header', () => {
  const log = 'Layer count: 2\n;FLAVOR:Marlin\n;TIME:4321\n;Filament used: 0.01m\nPrint time (s): 4321\n';
  assert.equal(parseCuraGcode(GCODE, { ...UNIT, log }).print_time_s, 4321);
  assert.equal(parseCuraGcode(GCODE.replace(';TIME:6666', ';TIME:777'), UNIT).print_time_s, 777);
});

test('G91 makes positions and E relative, G90 absolute again; nothing counts outside ;TYPE:', () => {
  const r = parseCuraGcode([
    'G90', 'G1 X1 Y1 Z1 E5', // no ;TYPE: yet
    ';LAYER:0', ';TYPE:SUPPORT', 'G91', 'G1 X3 Y4 E0.5', 'G1 X3 Y4 E0.5', 'G90', 'G1 X7 Y9 E7', 'G1 X7 Y9 E8',
  ].join('\n'), UNIT);
  close(r.support_volume_mm3, 3, 'support volume');  // 0.5 + 0.5 + (7 - 6) + (8 - 7)
  close(r.support_path_mm, 10, 'support path');       // two 5 mm relative moves, then none
  assert.equal(r.layers, 1);
  assert.equal(r.print_time_s, null);
});

test('the paper settings as CuraEngine needs them (derived values computed)', () => {
  const s = curaSettings();
  assert.equal(s.layer_height, 0.4);
  assert.equal(s.infill_sparse_density, 20);
  assert.equal(s.infill_pattern, 'grid');
  assert.equal(s.infill_line_distance, 4);   // grid: line width x 100 / density x 2
  assert.equal(s.infill_sparse_thickness, 0.4);
  assert.equal(s.support_enable, true);
  assert.equal(s.support_type, 'everywhere');
  assert.equal(s.support_angle, 45);
  assert.equal(s.material_diameter, 1.75);
  assert.equal(s.top_layers, 2);
  assert.equal(s.wall_line_count, 2);
  assert.equal(curaSettings({ supports: false }).support_enable, false);
});
