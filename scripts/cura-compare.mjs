#!/usr/bin/env node
// SPDX-License-Identifier: MIT
// CuraEngine 4.13 (Debian `cura-engine`) on a model placed the way Omnislice places it, printed
// along the fixed +Z direction: the reference of paper 000's Table I (support volume "Fixed Dir.",
// printing time measured with Cura at 0.4 mm layers and 20% grid infill). Used by scripts/bench.mjs
// (issue 7); never part of `npm test`.
//
//   node scripts/cura-compare.mjs MESH [--up AXIS] [--scale S] [--fit-mm MM] [--layer-height MM]
//        [--set KEY=VALUE ...] [-o OUT.json]
//
// The mesh goes through `omnislice info MESH --export-stl` (same placement options as the slicer:
// repaired, scaled, up axis turned to +Z, bbox centred on x = y = 0, min z = 0), then
// `CuraEngine slice -j fdmprinter.def.json` with supports on, and once more with supports off.
// CuraEngine and the definitions come from scripts/install-cura.sh (Debian packages only).
// Prints / returns {version, settings, print_time_s, filament_mm, total_volume_mm3,
// support_volume_mm3, support_path_mm, model_volume_mm3, layers, ms, by_type_mm3,
// without_supports: {...}}; or {skipped: reason} when CuraEngine cannot be installed.
import { execFileSync, spawnSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const CLI = process.env.OMNISLICE_CLI || path.join(ROOT, 'build/native/omnislice');

// CuraEngine writes its header before slicing, with these placeholders; the real figures are
// only in the header it logs with -v (the Cura front end patches them into the file).
const PLACEHOLDER_TIME = 6666;

const isSupportType = (type) => type === 'SUPPORT' || type === 'SUPPORT-INTERFACE';

// Extrusion per ;TYPE: section of a Marlin-flavour G-code. Handles absolute (M82, G90) and
// relative (M83, G91) E, G92 E resets, and retractions: a negative E step is a retraction, and a
// positive step first repays what was retracted (the prime) before anything counts as extrusion.
// Moves before the first ;TYPE: (start G-code prime) are not counted.
// Returns {print_time_s, print_time_source, time_elapsed_s, layers, filament_mm,
// total_volume_mm3, support_volume_mm3, support_path_mm, model_volume_mm3, by_type_mm3}.
// log: CuraEngine's -v output, whose echoed header carries the real ;TIME:.
export function parseCuraGcode(text, { filamentDiameterMm = 1.75, log = '' } = {}) {
  const area = Math.PI * (filamentDiameterMm / 2) ** 2;
  let absXYZ = true, absE = true;
  const pos = { X: 0, Y: 0, Z: 0 };
  let e = 0;          // current E coordinate
  let debt = 0;       // filament retracted and not yet primed back
  let type = null;
  let headerTime = null, timeElapsed = null, layerCount = null, layersSeen = 0;
  const byType = {};  // type -> filament mm
  let supportPath = 0;
  for (const raw of text.split('\n')) {
    const line = raw.trim();
    if (!line) continue;
    if (line[0] === ';') {
      if (line.startsWith(';TYPE:')) type = line.slice(6).trim();
      else if (line.startsWith(';LAYER:')) layersSeen++;
      else if (line.startsWith(';TIME_ELAPSED:')) timeElapsed = Number(line.slice(14));
      else if (line.startsWith(';TIME:') && headerTime === null) headerTime = Number(line.slice(6));
      else if (line.startsWith(';LAYER_COUNT:')) layerCount = Number(line.slice(13));
      continue;
    }
    const code = line.split(';')[0].trim().toUpperCase();
    const words = code.split(/\s+/);
    const cmd = words[0];
    const args = {};
    for (const w of words.slice(1)) if (/^[A-Z]/.test(w)) args[w[0]] = Number(w.slice(1));
    if (cmd === 'M82') absE = true;
    else if (cmd === 'M83') absE = false;
    else if (cmd === 'G90') { absXYZ = true; absE = true; }
    else if (cmd === 'G91') { absXYZ = false; absE = false; }
    else if (cmd === 'G92') {
      if ('E' in args) e = args.E;
      for (const k of ['X', 'Y', 'Z']) if (k in args) pos[k] = args[k];
    } else if (cmd === 'G0' || cmd === 'G1' || cmd === 'G00' || cmd === 'G01') {
      const from = { ...pos };
      for (const k of ['X', 'Y', 'Z']) if (k in args) pos[k] = absXYZ ? args[k] : pos[k] + args[k];
      if (!('E' in args) || Number.isNaN(args.E)) continue;
      const de = absE ? args.E - e : args.E;
      e = absE ? args.E : e + args.E;
      let extruded = 0;
      if (de < 0) debt -= de;
      else {
        const prime = Math.min(de, debt);
        debt -= prime;
        extruded = de - prime;
      }
      if (extruded <= 0 || type === null) continue;
      byType[type] = (byType[type] || 0) + extruded;
      if (isSupportType(type)) supportPath += Math.hypot(pos.X - from.X, pos.Y - from.Y, pos.Z - from.Z);
    }
  }
  let printTime = null, source = null;
  const logged = /^;TIME:(\d+(?:\.\d+)?)\s*$/m.exec(log) || /Print time \(s\):\s*(\d+(?:\.\d+)?)/.exec(log);
  if (logged) { printTime = Number(logged[1]); source = 'engine log header'; }
  else if (headerTime !== null && headerTime !== PLACEHOLDER_TIME) { printTime = headerTime; source = 'gcode header'; }
  else if (timeElapsed !== null) { printTime = timeElapsed; source = 'last ;TIME_ELAPSED'; }
  const filament = Object.values(byType).reduce((a, v) => a + v, 0);
  const support = Object.entries(byType).filter(([t]) => isSupportType(t)).reduce((a, [, v]) => a + v, 0);
  const by_type_mm3 = Object.fromEntries(Object.entries(byType).map(([t, v]) => [t, v * area]));
  return {
    print_time_s: printTime,
    print_time_source: source,
    time_elapsed_s: timeElapsed,
    layers: layerCount ?? layersSeen,
    filament_mm: filament,
    total_volume_mm3: filament * area,
    support_volume_mm3: support * area,
    support_path_mm: supportPath,
    model_volume_mm3: (filament - support) * area,
    by_type_mm3,
  };
}

// The paper's settings (Table I: 0.4 mm layers, 20% grid infill; support overhang 45 degrees,
// support everywhere; 0.4 mm nozzle and lines; PLA 1.75 mm). CuraEngine reads only the
// definitions' default_value, not their formulas, so every value derived from these (line
// distances, layer counts, sparse thicknesses, wall count) is computed here as Cura would.
export function curaSettings({ layerHeightMm = 0.4, lineWidthMm = 0.4, infillPercent = 20, supportAngleDeg = 45,
  filamentDiameterMm = 1.75, supports = true, bedMm = 300 } = {}) {
  const lh = layerHeightMm, lw = lineWidthMm;
  const supportInfillRate = 15;  // fdmprinter's default for normal supports, zigzag pattern
  const wallThickness = 0.8, topBottomThickness = 0.8;
  const round = (v) => Number(v.toFixed(4));
  return {
    machine_width: bedMm, machine_depth: bedMm, machine_height: bedMm,
    machine_gcode_flavor: 'RepRap (Marlin/Sprinter)',
    machine_nozzle_size: lw, material_diameter: filamentDiameterMm,
    line_width: lw, wall_line_width: lw, wall_line_width_0: lw, wall_line_width_x: lw, skin_line_width: lw,
    infill_line_width: lw, support_line_width: lw, support_interface_line_width: lw,
    support_roof_line_width: lw, support_bottom_line_width: lw, skirt_brim_line_width: lw, roofing_line_width: lw,
    layer_height: lh, layer_height_0: lh,
    wall_thickness: wallThickness, wall_line_count: Math.max(1, Math.round((wallThickness - lw) / lw) + 1),
    top_bottom_thickness: topBottomThickness, top_thickness: topBottomThickness, bottom_thickness: topBottomThickness,
    top_layers: Math.ceil(round(topBottomThickness / lh)), bottom_layers: Math.ceil(round(topBottomThickness / lh)),
    infill_sparse_density: infillPercent, infill_pattern: 'grid',
    infill_line_distance: infillPercent === 0 ? 0 : round((lw * 100) / infillPercent * 2),
    infill_sparse_thickness: lh,
    support_enable: supports, support_type: 'everywhere', support_angle: supportAngleDeg,
    support_pattern: 'zigzag', support_infill_rate: supportInfillRate,
    support_line_distance: round((lw * 100) / supportInfillRate),
    support_initial_layer_line_distance: round((lw * 100) / supportInfillRate),
    support_infill_sparse_thickness: lh,
    adhesion_type: 'none',
  };
}

let cachedEngine;
// {engine, definitions, version} or {skipped: reason}. Runs scripts/install-cura.sh (idempotent;
// installs with apt when running as root) unless CURA_DEFINITIONS_DIR names the definitions.
export function findCura() {
  if (cachedEngine) return cachedEngine;
  let definitions = process.env.CURA_DEFINITIONS_DIR;
  if (!definitions) {
    const r = spawnSync('bash', [path.join(ROOT, 'scripts/install-cura.sh')], { encoding: 'utf8' });
    if (r.status !== 0) {
      const why = (r.stderr || '').trim().split('\n').filter(Boolean).pop() || `exit code ${r.status}`;
      return (cachedEngine = { skipped: `CuraEngine not available (${why})` });
    }
    definitions = r.stdout.trim().split('\n').pop();
  }
  if (!fs.existsSync(path.join(definitions, 'fdmprinter.def.json'))) {
    return (cachedEngine = { skipped: `no fdmprinter.def.json in ${definitions}` });
  }
  const v = spawnSync('CuraEngine', ['help'], { encoding: 'utf8' });
  if (v.error) return (cachedEngine = { skipped: `CuraEngine cannot run (${v.error.message})` });
  const m = /version\s+(\S+)/.exec(`${v.stdout}${v.stderr}`);
  return (cachedEngine = { engine: 'CuraEngine', definitions, version: m ? m[1] : 'unknown' });
}

// Place MESH as Omnislice does and write it as a binary STL; returns the `omnislice info` JSON.
export function exportPlacedStl(mesh, out, { up, scale, fitMm } = {}) {
  const args = ['info', mesh, '--export-stl', out];
  if (up) args.push('--up', String(up));
  if (scale) args.push('--scale', String(scale));
  if (fitMm) args.push('--fit-mm', String(fitMm));
  return JSON.parse(execFileSync(CLI, args, { encoding: 'utf8', maxBuffer: 64 << 20 }));
}

// One CuraEngine run on a placed STL. settings: key -> value, set both globally and on
// extruder 0 (the extruder definition's own defaults, e.g. material_diameter 2.85, would
// otherwise win).
export function runCuraEngine(stl, settings, { cura = findCura(), workDir = os.tmpdir() } = {}) {
  const sets = Object.entries(settings).flatMap(([k, v]) => ['-s', `${k}=${v}`]);
  const gcode = path.join(workDir, `${path.basename(stl, '.stl')}-${settings.support_enable ? 'sup' : 'nosup'}.gcode`);
  const t0 = performance.now();
  const r = spawnSync(cura.engine, ['slice', '-v', '-j', path.join(cura.definitions, 'fdmprinter.def.json'),
    ...sets, '-e0', ...sets, '-l', stl, '-o', gcode], { encoding: 'utf8', maxBuffer: 256 << 20, timeout: 30 * 60e3 });
  const ms = performance.now() - t0;
  if (r.status !== 0) {
    const tail = `${r.stderr || ''}`.trim().split('\n').slice(-3).join(' | ');
    throw new Error(`CuraEngine failed (${r.error ? r.error.message : `exit ${r.status}`}): ${tail}`);
  }
  const log = `${r.stdout || ''}\n${r.stderr || ''}`;
  const parsed = parseCuraGcode(fs.readFileSync(gcode, 'utf8'), { filamentDiameterMm: settings.material_diameter, log });
  const logged = /Filament \(mm\^3\):\s*([\d.]+)/.exec(log);
  fs.rmSync(gcode, { force: true });
  return { ...parsed, engine_filament_mm3: logged ? Number(logged[1]) : null, ms };
}

// The comparison for one model: supports on (the Table I "Fixed Dir." figures) and off.
// placement: {up, scale, fitMm} as given to Omnislice. options: curaSettings() options plus
// `set` (extra CuraEngine settings). Returns {skipped} when CuraEngine is unavailable.
export function compareWithCura(mesh, placement = {}, options = {}) {
  const cura = findCura();
  if (cura.skipped) return { skipped: cura.skipped };
  const work = fs.mkdtempSync(path.join(os.tmpdir(), 'omnislice-cura-'));
  try {
    const stl = path.join(work, `${path.basename(mesh).replace(/\.[^.]+$/, '')}-placed.stl`);
    const info = exportPlacedStl(mesh, stl, placement);
    const box = info.placed_bbox || info.bbox;
    const size = Math.max(...[0, 1, 2].map((i) => box.max[i] - box.min[i]));
    const bedMm = Math.max(300, Math.ceil(size + 20));
    const settings = { ...curaSettings({ ...options, bedMm }), ...(options.set || {}) };
    const withSupports = runCuraEngine(stl, settings, { cura, workDir: work });
    const without = runCuraEngine(stl, { ...settings, support_enable: false }, { cura, workDir: work });
    const r3 = (v) => (typeof v === 'number' ? Number(v.toFixed(3)) : v);
    const tidy = (o) => Object.fromEntries(Object.entries(o).map(([k, v]) => [k,
      k === 'by_type_mm3' ? Object.fromEntries(Object.entries(v).map(([t, x]) => [t, r3(x)])) : r3(v)]));
    return {
      version: `CuraEngine ${cura.version}`,
      mesh: path.basename(mesh),
      placement: { up: placement.up || 'z', scale: placement.scale || 1, fit_mm: placement.fitMm || 0 },
      model_mesh_volume_mm3: r3(info.volume_mm3),
      settings,
      ...tidy(withSupports),
      without_supports: tidy(without),
    };
  } finally {
    fs.rmSync(work, { recursive: true, force: true });
  }
}

if (process.argv[1] && path.resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  const argv = process.argv.slice(2);
  const placement = {}, options = { set: {} };
  let mesh = null, out = null;
  for (let i = 0; i < argv.length; ++i) {
    const a = argv[i];
    if (a === '--up') placement.up = argv[++i];
    else if (a === '--scale') placement.scale = Number(argv[++i]);
    else if (a === '--fit-mm') placement.fitMm = Number(argv[++i]);
    else if (a === '--layer-height') options.layerHeightMm = Number(argv[++i]);
    else if (a === '--infill') options.infillPercent = Number(argv[++i]);
    else if (a === '--support-angle') options.supportAngleDeg = Number(argv[++i]);
    else if (a === '--set') {
      const [k, ...v] = argv[++i].split('=');
      options.set[k] = v.join('=');
    } else if (a === '-o') out = argv[++i];
    else if (a === '-h' || a === '--help') mesh = null, i = argv.length;
    else mesh = a;
  }
  if (!mesh) {
    console.error('usage: node scripts/cura-compare.mjs MESH [--up AXIS] [--scale S] [--fit-mm MM] ' +
      '[--layer-height MM] [--infill PCT] [--support-angle DEG] [--set KEY=VALUE ...] [-o OUT.json]');
    process.exit(2);
  }
  const result = compareWithCura(mesh, placement, options);
  const text = `${JSON.stringify(result, null, 2)}\n`;
  if (out) fs.writeFileSync(out, text);
  process.stdout.write(text);
  if (result.skipped) console.error(`[cura] skipped: ${result.skipped}`);
}
