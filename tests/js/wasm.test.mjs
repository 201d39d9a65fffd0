// SPDX-License-Identifier: MIT
// The wasm module in Node: same numbers as the native CLI on the same inputs, status codes from
// bad input as OmnisliceError codes, progress/cancel, results as heap copies.
import { before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { boxStl, lBracketStl, saddleObj, sphereStl, torusStl, writeBinaryStl } from './fixtures/meshes.js';
import { checkSearchLevels } from './search-levels.mjs';
import { CI, NATIVE_CLI, loadShipped, sharedModel, wasmUnavailable } from './wasm-support.mjs';

const why = wasmUnavailable();
if (why && CI) throw new Error(`wasm tests cannot run under CI: ${why}`);
const nativeWhy = fs.existsSync(NATIVE_CLI) ? null : `native CLI ${NATIVE_CLI} missing (scripts/build.sh native)`;
if (!why && nativeWhy && CI) throw new Error(nativeWhy);

const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'omnislice-wasm-test-'));
process.on('exit', () => fs.rmSync(tmp, { recursive: true, force: true }));

/** Relative closeness with a message. */
function close(actual, expected, rel, what) {
  const tol = rel * Math.max(1, Math.abs(expected));
  assert.ok(Math.abs(actual - expected) <= tol, `${what}: wasm ${actual} vs native ${expected} (tol ${tol})`);
}

function nativeSlice(file, settings) {
  const out = path.join(tmp, `${path.basename(file)}.gcode`);
  const report = path.join(tmp, `${path.basename(file)}.report.json`);
  const args = ['slice', file, '-o', out, '--report', report];
  for (const [k, v] of Object.entries(settings)) args.push('--set', `${k}=${v}`);
  execFileSync(NATIVE_CLI, args, { stdio: ['ignore', 'pipe', 'pipe'] });
  return { report: JSON.parse(fs.readFileSync(report, 'utf8')), program: fs.readFileSync(out, 'utf8') };
}

function nativeInfo(file) {
  return JSON.parse(execFileSync(NATIVE_CLI, ['info', file], { encoding: 'utf8' }));
}

describe('wasm module in Node', { skip: why ? `skipped: ${why}` : false }, () => {
  let m;
  let wrapper;
  before(async () => {
    ({ module: m, wrapper } = await loadShipped());
  });

  test('default settings come from the core (listSettings)', () => {
    const { values, keys } = m.defaultSettings();
    for (const k of ['layer_height', 'walls', 'infill', 'direction', 'up', 'fit_mm', 'scale']) {
      assert.ok(keys.includes(k), `default settings list ${k}`);
    }
    assert.equal(Number(values.layer_height), 0.2);
    assert.equal(Number(values.walls), 2);
    assert.equal(keys.length, Object.keys(values).length);
  });

  test('the settings schema is the core table: the same as the CLI prints, defaults as listed', { skip: nativeWhy || false }, () => {
    const schema = m.settingsSchema();
    const cli = JSON.parse(execFileSync(NATIVE_CLI, ['settings', '--schema'], { encoding: 'utf8' }));
    assert.deepEqual(schema, cli);
    const { values } = m.defaultSettings();
    const byKey = Object.fromEntries(schema.map((s) => [s.key, s]));
    // The listing resolves line_width (0 = 1.125 x nozzle), first_layer_height (0 = layer_height)
    // and motion.axis_freedom_deg (-1 = the method's).
    const resolved = { line_width: '0', first_layer_height: '0', 'motion.axis_freedom_deg': '-1' };
    for (const [key, text] of Object.entries(values)) {
      assert.ok(byKey[key], `listed key ${key} is in the schema`);
      assert.equal(byKey[key].default, resolved[key] ?? text, `${key} default`);
    }
    for (const s of schema) {
      if (s.type === 'number' || s.type === 'integer') {
        assert.ok(s.min < s.max, `${s.key} range`);
        assert.ok(Number(s.default) >= s.min && Number(s.default) <= s.max, `${s.key} default in range`);
      }
      if (s.type === 'choice') assert.ok(s.choices.includes(s.default), `${s.key} default is a choice`);
    }
    // A value outside a range is refused by the same table.
    const layer = byKey.layer_height;
    assert.throws(() => m.slice(new Uint8Array(boxStl(10, 10, 5)), 'box.stl', { layer_height: layer.max * 2 }),
      (e) => e.code === 'invalid_option' && /layer_height/.test(e.message));
  });

  // ---- parity with the native CLI --------------------------------------------------------------
  const settings = { layer_height: 0.3, walls: 2, infill: 20 };
  const cases = [
    ['generated torus', () => ({ name: 'torus.stl', bytes: new Uint8Array(torusStl(20, 6, 96, 32)) }), settings],
    ['generated sphere, direction tilted', () => ({ name: 'sphere.stl', bytes: new Uint8Array(sphereStl(12, 48, 24)) }),
      { ...settings, direction: '0,1,1' }],
    ['shared bunny (OBJ), fit 60 mm', () => {
      const f = sharedModel('compas_bunny_closed_low_res.obj');
      return f && { name: path.basename(f), bytes: fs.readFileSync(f), file: f };
    }, { ...settings, fit_mm: 60 }],
    ['shared kitten (OFF, y up)', () => {
      const f = sharedModel('pymdp_kitten.off');
      return f && { name: path.basename(f), bytes: fs.readFileSync(f), file: f };
    }, { ...settings, up: 'y', fit_mm: 50 }],
  ];
  for (const [label, make, s] of cases) {
    test(`same report numbers as the native CLI: ${label}`, { skip: nativeWhy || false }, (t) => {
      const input = make();
      if (!input) { t.skip('../shared/models absent'); return; }
      let file = input.file;
      if (!file) {
        file = path.join(tmp, input.name);
        fs.writeFileSync(file, input.bytes);
      }
      const native = nativeSlice(file, s);
      const wasm = m.slice(input.bytes, input.name, s);
      assert.ok(wasm.layers > 5, 'sliced into layers');
      assert.equal(wasm.report.layers, native.report.layers, 'layers');
      assert.equal(wasm.report.moves, native.report.moves, 'moves');
      for (const k of ['path_mm', 'extrusion_mm', 'travel_mm', 'estimated_time_s']) {
        close(wasm.report[k], native.report[k], 1e-6, k);
      }
      assert.ok(wasm.report.path_mm > 0 && wasm.report.extrusion_mm > 0);
      // info JSON of the same input
      const ni = nativeInfo(file);
      assert.equal(wasm.info.vertices, ni.vertices, 'vertices');
      assert.equal(wasm.info.faces, ni.faces, 'faces');
      close(wasm.info.volume_mm3, ni.volume_mm3, 1e-9, 'volume_mm3');
      const info = m.info(input.bytes, input.name, {});
      assert.equal(info.info.faces, ni.faces);
      close(info.info.volume_mm3, ni.volume_mm3, 1e-9, 'info volume_mm3');
      // Same G-code apart from the header's timestamp: every line has the same words, numbers equal
      // up to the last printed digit (cumulative E may round differently after 1e-12 drift).
      const a = wasm.program.split('\n');
      const b = native.program.split('\n');
      assert.equal(a.length, b.length, 'program line count');
      const stamp = /\d{4}-\d\d-\d\dT[\d:]+Z/;
      const mismatches = [];
      for (let i = 0; i < a.length; ++i) {
        if (a[i] === b[i] || a[i].replace(stamp, '') === b[i].replace(stamp, '')) continue;
        const wa = a[i].split(' ');
        const wb = b[i].split(' ');
        const same = wa.length === wb.length && wa.every((w, k) => {
          if (w === wb[k]) return true;
          const x = Number(w.slice(1));
          const y = Number(wb[k].slice(1));
          return w[0] === wb[k][0] && Number.isFinite(x) && Number.isFinite(y) && Math.abs(x - y) <= 1.5e-5;
        });
        if (!same) mismatches.push(`line ${i + 1}: wasm "${a[i]}" native "${b[i]}"`);
      }
      assert.deepEqual(mismatches.slice(0, 5), [], `${mismatches.length} program lines differ`);
    });
  }

  // Issue 4: the voxel method gives the same field, layers and paths in wasm and natively.
  test('same voxel report as the native CLI: generated sphere on table5', { skip: nativeWhy || false }, () => {
    // verify = warn: the sphere's underside is short of the soundness criteria (issue 25); this
    // test compares native and wasm figures.
    const s = { method: 'voxel', machine: 'table5', nozzle_diameter: 0.8, layer_height: 0.6, line_width: 0.9, verify: 'warn' };
    const bytes = new Uint8Array(sphereStl(7, 48, 24));
    const file = path.join(tmp, 'voxel-sphere.stl');
    fs.writeFileSync(file, bytes);
    const native = nativeSlice(file, s);
    const wasm = m.slice(bytes, 'voxel-sphere.stl', s);
    for (const k of ['voxels', 'solid_voxels', 'missed_voxels', 'field_layers', 'layers', 'regions', 'paths']) {
      assert.equal(wasm.report.voxel[k], native.report.voxel[k], `voxel.${k}`);
    }
    // The field, layers and regions are integer results and equal exactly. The spirals and the
    // orientation go through libm (glibc natively, musl in wasm), whose last-bit differences can
    // move a resampled point or flip a retract decision: a handful of moves out of thousands.
    console.log(`voxel parity: moves wasm ${wasm.report.moves} native ${native.report.moves}, path ` +
      `${wasm.report.path_mm} / ${native.report.path_mm}`);
    close(wasm.report.moves, native.report.moves, 2e-3 * native.report.moves, 'moves');
    for (const k of ['path_mm', 'extrusion_mm']) close(wasm.report[k], native.report[k], 1e-3 * native.report[k], k);
    close(wasm.report.voxel.thickness.mean_mm, native.report.voxel.thickness.mean_mm, 1e-3, 'thickness mean');
    const p = wasm.preview;
    assert.equal(p.axes.length, 3 * p.features.length, 'an axis per segment');
    assert.equal(p.surfaceLayers.length * 3, p.surfaceTriangles.length, 'a layer per surface triangle');
    assert.ok(p.voxelWidth > 0.6 && p.voxelWidth < 0.7, `voxel width ${p.voxelWidth}`);
  });

  // Issue 28 item 1: method = auto runs every method table5 takes and delivers the same choice as
  // the native CLI, with the chosen method's program.
  test('method = auto on table5: the native CLI\'s candidates and choice', { skip: nativeWhy || false }, () => {
    const s = { method: 'auto', machine: 'table5', nozzle_diameter: 0.8, layer_height: 0.6, line_width: 0.9 };
    const bytes = new Uint8Array(lBracketStl());
    const file = path.join(tmp, 'auto-l.stl');
    fs.writeFileSync(file, bytes);
    // One after another natively too (wasm always is): the same candidates stop early.
    const native = nativeSlice(file, { ...s, threads: 1 });
    const stages = [];
    const wasm = m.slice(bytes, 'auto-l.stl', s, { onProgress: (p) => { stages.push(p.stage); } });
    const names = (r) => r.auto.candidates.map((c) => `${c.method}:${c.status}`);
    assert.deepEqual(names(wasm.report), names(native.report));
    assert.deepEqual(wasm.report.auto.candidates.map((c) => c.method), ['planar', 'multidir', 'geodesic', 'voxel']);
    assert.equal(wasm.report.auto.chosen, native.report.auto.chosen);
    assert.equal(wasm.report.method, wasm.report.auto.chosen);
    assert.ok(wasm.report.verify.sound, wasm.report.auto.reason);
    assert.ok(stages.includes('auto'));
    assert.ok(wasm.program.includes(`; omnislice:setting method = ${wasm.report.auto.chosen}`), 'the chosen method\'s program');
  });

  // Issue 28 item 2: the page's pool (workers/auto-pool.js) over the core's plan and choice, with
  // candidates run "in" 1 and 3 lanes, finishing in any order, one of them lost: the delivered
  // program is the one the core's own method = auto delivers, the auto section the same.
  test('method = auto in a pool: the core\'s plan and choice deliver the same program as in one call', async () => {
    const { runAutoPool } = await import('../../workers/auto-pool.js');
    const s = { method: 'auto', machine: 'table5', nozzle_diameter: 0.8, layer_height: 0.6, line_width: 0.9 };
    const bytes = new Uint8Array(lBracketStl());
    const whole = m.slice(bytes, 'auto-l.stl', s);
    const plan = m.autoPlan(bytes, 'auto-l.stl', s);
    assert.deepEqual(plan.candidates.map((c) => c.method), ['planar', 'multidir', 'geodesic', 'voxel']);
    const sliced = plan.candidates.map((c) => m.slice(bytes, 'auto-l.stl', { ...s, ...c.settings }));
    // In one call (one after another) a candidate that cannot win stops before its check; in the
    // pool every one is checked. Those checked in both have the same figures.
    const same = (a, b) => {
      assert.equal(a.chosen, b.chosen);
      a.candidates.forEach((c, i) => {
        assert.equal(c.method, b.candidates[i].method);
        if (c.stopped_early || b.candidates[i].stopped_early) return;
        const { timings_ms: _a, ...x } = c;
        const { timings_ms: _b, ...y } = b.candidates[i];
        assert.deepEqual(x, y);
      });
    };
    for (const size of [1, 3]) {
      const lanes = new Set();
      const events = [];
      const r = await runAutoPool({
        plan, settings: s, size,
        // Each candidate finishes after a delay of its own, in reverse of the plan's order.
        run: (lane, k, settings) => {
          lanes.add(lane);
          assert.deepEqual(settings, { ...s, ...plan.candidates[k].settings });
          return new Promise((resolve) => setTimeout(() => resolve(sliced[k]), 5 * (4 - k)));
        },
        choose: async (candidates) => m.autoChoose(s, candidates),
        onProgress: (p) => events.push(p),
      });
      assert.ok(lanes.size <= size && lanes.size >= 1);
      assert.equal(r.decision.status, 'ok');
      assert.equal(r.result.program.slice(r.result.program.indexOf('\n')), whole.program.slice(whole.program.indexOf('\n')));
      same(r.decision.auto, whole.report.auto);
      assert.ok(r.decision.auto.candidates.every((c) => !c.stopped_early && c.status === 'ok'));
      assert.deepEqual(events.filter((e) => e.stage === 'auto').map((e) => e.fraction), [0, 0.25, 0.5, 0.75, 1]);
    }
    // A candidate whose worker is lost is reported as such; the others still decide.
    const lost = await runAutoPool({
      plan, settings: s, size: 2,
      run: async (lane, k) => {
        if (plan.candidates[k].method === whole.report.auto.chosen) throw Object.assign(new Error('slicer worker crashed'), { code: 'worker_failed' });
        return sliced[k];
      },
      choose: async (candidates) => m.autoChoose(s, candidates),
    });
    const gone = lost.decision.auto.candidates.find((c) => c.method === whole.report.auto.chosen);
    assert.equal(gone.status, 'worker_failed');
    assert.equal(gone.verify, null);
    assert.notEqual(lost.decision.auto.chosen, whole.report.auto.chosen);
    assert.equal(lost.result.report.method, lost.decision.auto.chosen);
    // Cancelled: the pool passes the cancel on.
    await assert.rejects(runAutoPool({
      plan, settings: s, size: 2,
      run: async () => { throw Object.assign(new Error('cancelled'), { code: 'cancelled' }); },
      choose: async (candidates) => m.autoChoose(s, candidates),
    }), (e) => e.code === 'cancelled');
    assert.throws(() => m.autoChoose(s, [{ method: 'planar', status: 'ok', report: {} }]), (e) => e.code === 'invalid_option');
  });

  // Issue 7: the multidir method (paper 000) finds the same planes, parts and projected supports in
  // wasm and natively (the search is deterministic; the slicer works on integers).
  test('same multidir report as the native CLI: the Kitten on table5 with projected supports', { skip: nativeWhy || false }, (t) => {
    const file = sharedModel('pymdp_kitten.off');
    if (!file) return t.skip('../shared/models absent');
    const s = { method: 'multidir', machine: 'table5', up: 'y', fit_mm: 60, layer_height: 0.3 };
    const native = nativeSlice(file, s);
    const wasm = m.slice(new Uint8Array(fs.readFileSync(file)), 'pymdp_kitten.off', s);
    const a = wasm.report.multidir, b = native.report.multidir;
    console.log(`multidir parity: J_G ${b.J_G_before} -> ${b.J_G_after}, ${b.part_count} parts, support ` +
      `${b.support_volume_mm3} mm3; wasm ${a.J_G_after}, ${a.part_count}, ${a.support_volume_mm3}`);
    assert.equal(a.part_count, b.part_count, 'parts');
    close(a.J_G_before, b.J_G_before, 1e-9, 'J_G before');
    close(a.J_G_after, b.J_G_after, 1e-6, 'J_G after');
    // The local search ran (this Kitten ends its restarts above 0.1 mm^2) and took the same moves.
    assert.ok(b.search.perturbations > 0, 'local search moves tried');
    assert.equal(a.search.perturbations, b.search.perturbations, 'local search moves');
    assert.equal(a.search.perturbations_kept, b.search.perturbations_kept, 'local search moves kept');
    a.parts.forEach((p, i) => {
      for (let k = 0; k < 3; k++) close(p.direction[k], b.parts[i].direction[k], 1e-9, `part ${i} direction`);
      assert.equal(p.layers, b.parts[i].layers, `part ${i} layers`);
    });
    assert.equal(a.supports_generated, true);
    for (const k of ['samples', 'struts', 'roofs', 'blocked', 'landed_on_model', 'landed_on_platform']) {
      assert.equal(a.supports[k], b.supports[k], `supports.${k}`);
    }
    close(a.support_volume_mm3, b.support_volume_mm3, 1e-3, 'support volume');
    close(wasm.report.moves, native.report.moves, 2e-3 * native.report.moves, 'moves');
  });

  // Issue 5: the surface method (paper 003) gives the same theta*, curve and paths in wasm and natively.
  test('same iso-planar report as the native CLI: saddle surface on robot6', { skip: nativeWhy || false }, () => {
    const s = { method: 'surface', machine: 'robot6-ur5', nozzle_diameter: 1, layer_height: 0.75, line_width: 1.125,
      'isoplanar.directions': 60, verify: 'warn' };
    const text = saddleObj(50, 15, 24);
    const bytes = new TextEncoder().encode(text);
    const file = path.join(tmp, 'saddle.obj');
    fs.writeFileSync(file, text);
    const native = nativeSlice(file, s).report.isoplanar;
    const wasm = m.slice(bytes, 'saddle.obj', s).report.isoplanar;
    for (const k of ['theta_deg', 'planes', 'curves', 'paths', 'samples', 'unreachable', 'base_layers']) {
      assert.equal(wasm[k], native[k], `isoplanar.${k}`);
    }
    assert.equal(wasm.curve.length, native.curve.length);
    for (let i = 0; i < wasm.curve.length; ++i) close(wasm.curve[i][1], native.curve[i][1], 1e-6, `v_e(${wasm.curve[i][0]})`);
    for (const k of ['deposition_rate_mm3_s', 'path_mm', 'estimated_time_s']) close(wasm[k], native[k], 1e-6, k);
    // 59 directions' plans averaged: libm's last bits (glibc vs musl) add up to ~2e-6.
    close(wasm.benchmark.mean_estimated_time_s, native.benchmark.mean_estimated_time_s, 1e-4, 'benchmark time');
  });

  test('torus preview and mesh: counts agree with the report and are heap copies', () => {
    const r = m.slice(torusStl(20, 6, 96, 32), 'torus.stl', settings);
    assert.equal(r.report.layers, 40, '12 mm high at 0.3 mm');
    const n = r.preview.features.length;
    assert.ok(n > 0);
    assert.equal(r.preview.positions.length, 6 * n);
    assert.equal(r.preview.layers.length, n);
    assert.equal(r.preview.machine.length, 6 * n, 'machine values per segment');
    assert.equal(r.programExtension, 'gcode');
    assert.equal(Math.max(...r.preview.layers), r.report.layers - 1);
    assert.equal(r.mesh.indices.length, 3 * 2 * 96 * 32);
    // NL curve indices (iso-planar fill): a Uint32Array, empty or one per segment.
    assert.ok(r.preview.curves instanceof Uint32Array, 'preview.curves');
    assert.ok(r.preview.curves.length === 0 || r.preview.curves.length === n, `curves: ${r.preview.curves.length}`);
    for (const a of [r.preview.positions, r.preview.features, r.preview.layers, r.preview.machine, r.preview.curves, r.mesh.positions, r.mesh.indices]) {
      assert.equal(a.byteOffset, 0);
      assert.equal(a.buffer.byteLength, a.byteLength, 'own buffer, not a view of the wasm heap');
    }
    // Printed z values stay within the placed part's height.
    let zmax = -Infinity;
    for (let i = 2; i < r.preview.positions.length; i += 3) zmax = Math.max(zmax, r.preview.positions[i]);
    assert.ok(zmax <= 12 + 0.3 + 1e-3, `preview z max ${zmax}`);
    // A later slice that grows the heap leaves earlier results intact.
    const before = Array.from(r.preview.positions.subarray(0, 60));
    const machineBefore = Array.from(r.preview.machine.subarray(0, 60));
    m.slice(sphereStl(40, 300, 150), 'big.stl', { layer_height: 0.4 });
    assert.deepEqual(Array.from(r.preview.positions.subarray(0, 60)), before);
    assert.deepEqual(Array.from(r.preview.machine.subarray(0, 60)), machineBefore);
  });

  // ---- status codes from bad input -------------------------------------------------------------
  const expectCode = (fn, code) => assert.throws(fn, (e) => {
    assert.ok(e instanceof wrapper.OmnisliceError, `OmnisliceError, got ${e}`);
    assert.equal(e.code, code, e.message);
    assert.ok(e.message.length > 0);
    return true;
  });

  test('empty input -> empty_input', () => {
    expectCode(() => m.slice(new Uint8Array(0), 'a.stl'), 'empty_input');
    expectCode(() => m.info(new ArrayBuffer(0), 'a.obj'), 'empty_input');
  });

  test('garbage -> parse_error / unsupported_format / truncated_file', () => {
    const junk = new Uint8Array(1000);
    for (let i = 0; i < junk.length; ++i) junk[i] = (i * 7919) % 251;
    expectCode(() => m.slice(junk, 'junk.bin'), 'unsupported_format');
    expectCode(() => m.slice(new TextEncoder().encode('v 1 2 3\nf 1 2 x\n'), 'bad.obj'), 'parse_error');
    const box = new Uint8Array(boxStl(10, 10, 10));
    expectCode(() => m.slice(box.subarray(0, 84 + 50 * 5), 'cut.stl'), 'truncated_file');
  });

  test('NaN vertex -> non_finite_vertex', () => {
    const v = new Float32Array([0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, NaN]);
    const stl = writeBinaryStl(v, [0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2]);
    expectCode(() => m.slice(stl, 'nan.stl'), 'non_finite_vertex');
  });

  test('open mesh: repair = auto closes it (report and info say so); repair = none -> open_mesh', () => {
    const box = new Uint8Array(boxStl(10, 10, 10));
    const open = new Uint8Array(box.subarray(0, 84 + 50 * 11));
    new DataView(open.buffer).setUint32(80, 11, true);
    expectCode(() => m.slice(open, 'open.stl', { repair: 'none' }), 'open_mesh');
    const none = m.info(open, 'open.stl', { repair: 'none' }).info;
    assert.equal(none.closed, false);
    assert.ok(none.boundary_edges >= 3, `boundary edges ${none.boundary_edges}`);
    const { info } = m.info(open, 'open.stl');
    assert.equal(info.closed, true);
    assert.equal(info.repair.holes_filled, 1);
    assert.ok(Math.abs(info.volume_mm3 - 1000) < 1e-6, `volume ${info.volume_mm3}`);
    const sliced = m.slice(open, 'open.stl');
    assert.equal(sliced.report.mesh.repair.holes_filled, 1);
    assert.ok(sliced.report.mesh.repairs.some((r) => r.startsWith('filled 1 hole')), sliced.report.mesh.repairs.join('; '));
    // The same program as from the closed box: the hole was one flat triangle of a side.
    // (From the second line: the first one carries the time, which may tick between the slices.)
    const afterDate = (text) => text.slice(text.indexOf('\n'));
    assert.equal(afterDate(sliced.program), afterDate(m.slice(box, 'open.stl').program));
  });

  test('absurd or unknown settings -> invalid_option', () => {
    const box = boxStl(10, 10, 10);
    expectCode(() => m.slice(box, 'b.stl', { layer_height: 1e9 }), 'invalid_option');
    expectCode(() => m.slice(box, 'b.stl', { layer_height: -0.2 }), 'invalid_option');
    expectCode(() => m.slice(box, 'b.stl', { walls: 'many' }), 'invalid_option');
    expectCode(() => m.slice(box, 'b.stl', { no_such_key: 1 }), 'invalid_option');
    expectCode(() => m.slice(box, 'b.stl', { direction: '0,0,0' }), 'invalid_option');
    expectCode(() => m.slice(box, 'b.stl', { layer_height: NaN }), 'invalid_option');
    expectCode(() => m.info(box, 'b.stl', { scale: 0 }), 'invalid_option');
  });

  test('progress: stages in order, nondecreasing; returning false cancels', () => {
    const events = [];
    m.slice(torusStl(20, 6, 48, 16), 't.stl', settings, { onProgress: (p) => { events.push(p); } });
    const order = [];
    const last = new Map();
    for (const { stage, fraction } of events) {
      if (order[order.length - 1] !== stage) {
        assert.ok(!order.includes(stage), `stage ${stage} repeated: ${order}`);
        order.push(stage);
      }
      assert.ok(!(fraction < (last.get(stage) ?? 0)), `${stage} went back to ${fraction}`);
      last.set(stage, fraction);
    }
    assert.equal(order[0], 'read');
    assert.equal(order[order.length - 1], 'program');
    for (const stage of ['slice', 'program']) assert.ok(order.includes(stage), `${stage} reported: ${order}`);
    let calls = 0;
    expectCode(() => m.slice(torusStl(20, 6, 48, 16), 't.stl', settings,
      { onProgress: ({ stage }) => { ++calls; return stage !== 'slice'; } }), 'cancelled');
    assert.ok(calls > 0);
    // The module keeps working after a cancel.
    assert.equal(m.slice(boxStl(10, 10, 3), 'b.stl', settings).report.layers, 10);
  });

  // Issue 7 item 9: the multidir plane search reports every level with its J_G (progress.search).
  test('progress: multidir search levels reach JS as progress.search; false on a level cancels', () => {
    const s = { method: 'multidir', machine: 'table5', layer_height: 0.3 };
    const events = [];
    const r = m.slice(lBracketStl(), 'l.stl', s, { onProgress: (p) => { events.push(p); } });
    const { chosen } = checkSearchLevels(events, r.report.multidir);
    assert.ok(chosen.length >= 2, `the bracket is cut: ${chosen}`);
    // multidir.restarts reaches the search: one restart, one beam line.
    const once = [];
    const r1 = m.slice(lBracketStl(), 'l.stl', { ...s, 'multidir.restarts': 1 }, { onProgress: (p) => { once.push(p); } });
    checkSearchLevels(once, r1.report.multidir, 1);
    assert.ok(events.filter((p) => !p.search).every((p) => !('search' in p)), 'plain reports carry no search');
    const decompose = events.filter((p) => p.stage === 'decompose').map((p) => p.fraction);
    decompose.forEach((f, i) => assert.ok(i === 0 || f >= decompose[i - 1], `decompose went back to ${f}`));
    // Cancelling on the beam's first level: Cancelled, and no report after it.
    let stopped = false;
    let after = 0;
    expectCode(() => m.slice(lBracketStl(), 'l.stl', s, {
      onProgress: (p) => {
        if (stopped) {
          after += 1;
          return false;
        }
        stopped = !!p.search && p.search.line === 'beam' && p.search.level === 1;
        return !stopped;
      },
    }), 'cancelled');
    assert.ok(stopped, 'the beam reached level 1');
    assert.equal(after, 0, 'reports after the cancel');
  });

  test('verify accepts the program sliced from the same mesh', () => {
    const bytes = torusStl(20, 6, 48, 16);
    const r = m.slice(bytes, 't.stl', settings);
    const v = m.verify(r.program, bytes, 't.stl');
    assert.equal(v.layers, r.report.layers, 'verify sees every layer');
    assert.equal(v.collisions, 0);
    assert.equal(v.limits, 0);
    assert.ok(v.inside > 0.99, `deposits inside the part: ${v.inside}`);
    close(v.extrusion_mm, r.report.extrusion_mm, 1e-4, 'verify extrusion_mm (G-code rounds to 3-5 decimals)');
    close(v.path_mm, r.report.path_mm, 1e-4, 'verify path_mm');
    // A program whose header does not match is refused with a status, not a crash.
    assert.throws(() => m.verify('G1 X1 Y1\n', bytes, 't.stl'), (e) => e instanceof wrapper.OmnisliceError);
  });

  test('Node: loadOmnislice reads omnislice.wasm itself when no wasmBinary is given', async () => {
    const { pathToFileURL } = await import('node:url');
    const { WASM_DIR } = await import('./wasm-support.mjs');
    const other = await wrapper.loadOmnislice({ moduleUrl: pathToFileURL(path.join(WASM_DIR, 'omnislice.mjs')).href });
    assert.equal(other.slice(boxStl(10, 10, 2), 'b.stl', { layer_height: 0.2 }).report.layers, 10);
  });

  test('settingsToLines validates keys and values', () => {
    assert.equal(wrapper.settingsToLines({ a: 1, b: true, c: [0, 0, 1], d: 'y', e: undefined }),
      'a=1\nb=true\nc=0,0,1\nd=y');
    assert.throws(() => wrapper.settingsToLines({ 'a=b': 1 }), { code: 'invalid_option' });
    assert.throws(() => wrapper.settingsToLines({ a: 'x\ny' }), { code: 'invalid_option' });
    assert.throws(() => wrapper.settingsToLines({ a: Infinity }), { code: 'invalid_option' });
  });

  test('out of memory: a budget refusal and a failed allocation are out_of_memory; the instance goes on', () => {
    // The code list mirrors core/common/status.cpp.
    const cpp = fs.readFileSync(new URL('../../core/common/status.cpp', import.meta.url), 'utf8');
    const codes = [...cpp.matchAll(/return "([a-z_]+)";/g)].map((x) => x[1]);
    assert.ok(codes.includes('out_of_memory'));
    for (const c of codes) assert.ok(wrapper.STATUS_CODES.includes(c), `STATUS_CODES lacks ${c}`);
    // A 40 mm cube in 0.32 mm voxels is over a 16 MB budget: refused before the grid exists.
    const cube = new Uint8Array(boxStl(40, 40, 40));
    assert.throws(() => m.slice(cube, 'cube.stl', { method: 'voxel', machine: 'table5', memory_mb: 16 }), (e) => {
      assert.equal(e.code, 'out_of_memory');
      assert.match(e.message, /needs about \d+ MB, more than the memory budget \(memory_mb = 16 MB\); raise voxel\.width_mm/);
      return true;
    });
    // verify has the same budget (memoryMb): the cube's 217 m of path in 0.5 mm samples.
    const planar = m.slice(cube, 'cube.stl', {}).program;
    assert.throws(() => m.verify(planar, cube, 'cube.stl', { memoryMb: 16 }), (e) => {
      assert.equal(e.code, 'out_of_memory');
      assert.match(e.message, /^verifying the program \(\d+ mm of path, \d+ samples\) needs about \d+ MB, more than the memory budget \(memory_mb = 16 MB\)/);
      return true;
    });
    assert.throws(() => m.verify(planar, cube, 'cube.stl', { memoryMb: NaN }), { code: 'invalid_option' });
    assert.ok(m.verify(planar, cube, 'cube.stl').inside > 0.99);
    // An allocation beyond the 4 GB heap: std::bad_alloc, caught, the same code.
    const failed = m.raw._allocateForTest(4000);
    assert.equal(failed.status, 'out_of_memory', failed.message);
    assert.match(failed.message, /ran out of memory/);
    assert.equal(m.raw._allocateForTest(1).status, 'ok');
    assert.equal(m.aborted, false);
    const after = m.slice(new Uint8Array(boxStl(10, 10, 5)), 'box.stl', {});
    assert.ok(after.program.length > 0);
  });
});
