// SPDX-License-Identifier: MIT
// The wasm module's machine output in Node, tied to the page's animation: the demo model sliced
// for every machine kind gives preview.machine with 6 values per preview segment, and the page's
// JS forward map (web/machine-kinematics.js) of every row, with the report's machine_profile,
// reproduces the segment's part-frame end point within 1e-3 mm (so the animation puts the nozzle
// on the deposition point). Also: the program extension and the header's format per machine and
// setting, and the page's settings fields against the core's table: each page field is in it,
// the defaults are the core's, and what the page sends in a slice request is accepted.
import { before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { CI, REPO, loadShipped, wasmUnavailable } from './wasm-support.mjs';
import { UR5_DH, forwardMap, machineAxisCount, machineKind, tipError, platformTransform, transformPoint4 } from '../../web/machine-kinematics.js';
import { PAGE_FIELDS, settingsFields } from '../../web/settings-fields.js';
import { SettingsModel } from '../../web/settings-panel.js';
import { PLACEMENT_KEYS } from '../../web/placement.js';
import { boxStl } from './fixtures/meshes.js';

const why = wasmUnavailable();
if (why && CI) throw new Error(`wasm tests cannot run under CI: ${why}`);

const DEMO = path.join(REPO, 'web', 'models', 'demo-overhang.stl');

describe('machine output of the wasm module (Node)', { skip: why ? `skipped: ${why}` : false }, () => {
  let m;
  let demo;
  before(async () => {
    ({ module: m } = await loadShipped());
    demo = fs.readFileSync(DEMO);
  });

  test('the page\'s settings fields: each in the core table, defaults the core\'s, every key it sends accepted', (t) => {
    // settingsFields throws, naming the key, for a page field the core's table does not have.
    const fields = settingsFields(m.settingsSchema());
    const coreKey = Object.fromEntries(PAGE_FIELDS.map((f) => [f.key, f.core || f.key]));
    // The built defaults against the core's own listing of its default settings (listSettings).
    // The method-specific choices, listed only with their method, against the table's text.
    const schema = Object.fromEntries(m.settingsSchema().map((s) => [s.key, s]));
    const { values } = m.defaultSettings();
    const unlisted = [];
    let compared = 0;
    for (const field of fields) {
      const key = coreKey[field.key];
      if (!(key in values)) {
        assert.equal(String(field.value), schema[key].default, `${field.key}: the table's default`);
        unlisted.push(key);
        continue;
      }
      let page = field.value;
      // line_width 0 means automatic; the core lists the resolved width (1.125 x nozzle).
      if (field.key === 'line_width' && page === 0) page = 1.125 * fields.find((f) => f.key === 'nozzle').value;
      // motion.axis_freedom_deg -1 means the method's; the core lists it for its default method.
      if (field.key === 'motion.axis_freedom_deg' && page === -1) page = values.method === 'geodesic' ? 25 : 15;
      const core = values[key];
      if (typeof page === 'number') assert.ok(Math.abs(Number(core) - page) < 1e-9, `${field.key}: core ${core}, page ${page}`);
      else if (typeof page === 'boolean') assert.equal(core, String(page), field.key);
      else if (field.type === 'direction') assert.deepEqual(core.split(',').map(Number), page.split(',').map(Number), field.key);
      else assert.equal(core, page, field.key);
      compared++;
    }
    t.diagnostic(`${compared} defaults compared with the listing; with the table only: ${unlisted.join(', ') || 'none'}`);
    assert.ok(compared >= 20);
    // Every key the page may send, at its default, is read by the core (machines() reads the
    // settings and refuses an unknown key or value).
    const model = new SettingsModel(fields);
    assert.doesNotThrow(() => m.machines(model.toSettings()), 'every page key accepted');
    // A slice request as the page makes it: at the defaults (the placement keys only), then after
    // edits of each input type (the alias 'nozzle' too); the core applies what was sent.
    const box = new Uint8Array(boxStl(10, 10, 5));
    assert.deepEqual(Object.keys(model.toSliceSettings()).sort(), [...PLACEMENT_KEYS].sort());
    assert.ok(m.slice(box, 'box.stl', model.toSliceSettings()).report.layers > 0);
    const edits = { infill: 35, walls: 3, nozzle: 0.5, layer_height: 0.3, infill_pattern: 'lines', direction: '0,-0.5,1',
      gcode_flavor: 'klipper', center: false, 'motion.smooth_orientations': false, 'voxel.smooth': 9 };
    for (const [key, value] of Object.entries(edits)) model.set(key, value);
    const sent = model.toSliceSettings();
    assert.equal('voxel.smooth' in sent, false, 'the voxel settings stay out of a planar request');
    const applied = m.slice(box, 'box.stl', sent).report.settings;
    for (const [key, value] of Object.entries(sent)) {
      // Keys the core does not list in a program's settings (repair: a repaired mesh's program can
      // only come from repair = auto) cannot be read back; they were accepted above.
      if (!(coreKey[key] in applied) && unlisted.includes(coreKey[key])) continue;
      const core = applied[coreKey[key]];
      if (typeof value === 'number') assert.ok(Math.abs(Number(core) - value) < 1e-9, `${key}: sent ${value}, core ${core}`);
      else if (key === 'direction') core.split(',').forEach((x, i) => assert.ok(Math.abs(Number(x) - Number(value.split(',')[i])) < 1e-4, `direction ${core}`));
      else assert.equal(core, String(value), key);
    }
  });

  const cases = [
    ['cartesian3', {}, 'gcode'],
    ['rotary4', {}, 'gcode'],
    ['table5', { gcode_flavor: 'klipper' }, 'gcode'],
    ['robot6-ur5', { robot_format: 'csv' }, 'csv'],
    // (coarser layers: the same checks, half the robot planning time)
    ['robot6-ur5', { robot_format: 'urscript', layer_height: 0.4 }, 'script'],
    // An industrial arm (spherical wrist) in its controller's language.
    ['robot6-kr6', { robot_format: 'krl', layer_height: 0.4 }, 'src'],
  ];
  for (const [machine, extra, extension] of cases) {
    test(`${machine} ${JSON.stringify(extra)}: every preview.machine row maps onto its segment end`, (t) => {
      const t0 = performance.now();
      const r = m.slice(demo, 'demo-overhang.stl', { machine, ...extra });
      const ms = performance.now() - t0;
      const { positions, features, machine: values } = r.preview;
      const S = features.length;
      assert.ok(S > 1000, `${S} segments`);
      assert.ok(values instanceof Float32Array);
      assert.equal(values.length, 6 * S, 'preview.machine: 6 values per segment');
      assert.equal(r.programExtension, extension);
      assert.equal(r.report.program_extension, extension);
      const profile = r.report.machine_profile;
      assert.ok(profile && typeof profile === 'object', 'report.machine_profile');
      const kind = machineKind(profile);
      assert.equal(kind, machineKind(machine));
      assert.equal(r.report.machine_kind, kind);
      // The header carries the same profile.
      const header = r.program.split('\n').find((l) => /omnislice:machine /.test(l));
      assert.ok(header, 'machine header line');
      assert.deepEqual(JSON.parse(header.slice(header.indexOf('{'))), profile, 'header machine = report.machine_profile');
      // Unused trailing values are 0.
      const n = machineAxisCount(kind);
      let worst = 0;
      let worstAt = -1;
      for (let s = 0; s < S; s++) {
        const row = Array.from(values.subarray(6 * s, 6 * s + 6));
        for (let k = n; k < 6; k++) assert.equal(row[k], 0, `segment ${s}: value ${k} unused`);
        const end = [positions[6 * s + 3], positions[6 * s + 4], positions[6 * s + 5]];
        const e = tipError(profile, row, end);
        if (e > worst) {
          worst = e;
          worstAt = s;
        }
      }
      t.diagnostic(`${machine}: ${S} segments, worst |forward(machine) - segment end| = ${worst.toExponential(2)} mm at ${worstAt}; slice ${ms.toFixed(0)} ms`);
      assert.ok(worst <= 1e-3, `${machine}: segment ${worstAt} is ${worst} mm off its machine values`);
      // A sample of rows through the part-frame forward map too (the inverse direction).
      for (let s = 0; s < S; s += Math.ceil(S / 50)) {
        const { tip } = forwardMap(profile, Array.from(values.subarray(6 * s, 6 * s + 6)));
        const end = [positions[6 * s + 3], positions[6 * s + 4], positions[6 * s + 5]];
        assert.ok(Math.hypot(tip[0] - end[0], tip[1] - end[1], tip[2] - end[2]) <= 1e-3, `segment ${s}`);
      }
      // Replaying the written program through its declared machine (the core's reader) gives
      // pieces whose machine values map onto their part-frame ends as well, with the same profile.
      const replay = m.replay(r.program);
      assert.deepEqual(replay.profile, profile, 'replayed machine = report.machine_profile');
      assert.equal(replay.format, { gcode: 'gcode', csv: 'csv', script: 'urscript', mod: 'rapid', src: 'krl' }[extension]);
      assert.equal(replay.layers, r.report.layers);
      const R = replay.preview.features.length;
      assert.equal(replay.preview.machine.length, 6 * R);
      assert.ok(R >= 0.9 * S, `replayed ${R} pieces for ${S} segments`);
      let worstReplay = 0;
      for (let s = 0; s < R; s++) {
        const row = Array.from(replay.preview.machine.subarray(6 * s, 6 * s + 6));
        const p = replay.preview.positions;
        worstReplay = Math.max(worstReplay, tipError(profile, row, [p[6 * s + 3], p[6 * s + 4], p[6 * s + 5]]));
      }
      t.diagnostic(`${machine}: replay ${R} pieces, worst ${worstReplay.toExponential(2)} mm`);
      assert.ok(worstReplay <= 1e-3, `replay: ${worstReplay} mm`);
      if (kind !== 'cartesian3') {
        // Not a trivial map: the platform really moves over the program.
        const first = platformTransform(profile, Array.from(values.subarray(0, 6)));
        let moved = 0;
        for (let s = 0; s < S; s += 97) {
          const W = platformTransform(profile, Array.from(values.subarray(6 * s, 6 * s + 6)));
          const a = transformPoint4(W, [10, 0, 0]);
          const b = transformPoint4(first, [10, 0, 0]);
          moved = Math.max(moved, Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]));
        }
        t.diagnostic(`${machine}: a part point 10 mm off the origin moves up to ${moved.toFixed(1)} mm in the machine frame`);
        if (kind === 'robot6') assert.ok(moved > 1, 'the robot moves the platform');
      }
    });
  }

  test('machines(): the built-ins in display order; each parses back to itself; UR5 DH as PROGRAM-FORMAT.md', () => {
    const list = m.machines();
    assert.deepEqual(list.map((x) => x.name), ['cartesian3', 'rotary4', 'table5', 'head4', 'head5', 'robot6-ur5', 'robot6-ur5-rated', 'robot6-irb1200', 'robot6-kr6']);
    for (const { name, profile, json } of list) {
      assert.equal(machineKind(profile), machineKind(name), name);
      assert.deepEqual(m.parseMachine(json).profile, profile, `${name}: parseMachine(machineJson) is itself`);
      assert.equal(profile.nozzle.diameter, 0.4, `${name}: default nozzle`);
    }
    const ur5 = list.find((x) => x.name === 'robot6-ur5').profile;
    assert.equal(ur5.dh.length, 6);
    ur5.dh.forEach((row, i) => row.forEach((v, k) => assert.ok(Math.abs(v - UR5_DH[i][k]) < 1e-12, `dh[${i}][${k}] = ${v}`)));
    assert.equal(ur5.flange_to_platform.length, 16);
    assert.equal(ur5.nozzle_tip.length, 3);
    // Sized by the settings: a 300 mm bed gives X limits of +-150 mm, a 0.6 mm nozzle its diameter.
    const big = m.machines({ bed_size: '300,300,300', nozzle: 0.6 });
    const c3 = big.find((x) => x.name === 'cartesian3').profile;
    assert.deepEqual(c3.axis_limits.X, [-150, 150]);
    assert.equal(c3.nozzle.diameter, 0.6);
    assert.throws(() => m.machines({ no_such_key: 1 }), (e) => e.code === 'invalid_option');
  });
});
