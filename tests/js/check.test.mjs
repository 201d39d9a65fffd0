// SPDX-License-Identifier: MIT
// The check before writing on the page (issue 25 item 6) in Node: the verdict and the figures
// rows of report.verify against the core's criteria (web/methods/check-data.js), the failing
// points as point clouds and their sprite, the view's clouds and toggle (check-view.js), and the
// check's place in the registry beside the methods (the done line gains its verdict). The verify
// sections below are the CLI's on the demo overhang on table5 (voxel at width 1.2 mm refused,
// geodesic refused, multidir sound).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import {
  COLLISION_COLOR, FAILING_POINTS, SOUNDNESS_CRITERIA, UNSUPPORTED_COLOR, attemptsText, checkDoneSummary, checkRows, checkVerdict, failingPoints,
  hasCheckPoints, pointCloud, pointCountText, ringSprite, shareText, verifySection,
} from '../../web/methods/check-data.js';
import { CheckView } from '../../web/methods/check-view.js';
import { EXTRAS, METHODS, check, doneSummary } from '../../web/methods/index.js';
import { FEATURES } from '../../web/preview.js';

const VOXEL_REFUSED = {
  mode: 'refuse', sound: false, inside: 1, coverage: 0.9401, coverage_judged: true, supported: 0.96512, supported_all: 0.98,
  collisions: 186, limits: 0, left_out_mm: 0, samples: 214637, ms: 570.2,
  failures: ['only 94.0 % of the interior is filled (at least 97.0 %)', '3.5 % of the surface is printed over air (at most 1.0 %)',
    '186 tool-path samples put the nozzle cone into material printed before'],
  statement: 'the voxel method cannot print this model soundly on table5: ...',
};
const MULTIDIR_SOUND = {
  mode: 'refuse', sound: true, inside: 1, coverage: 0.5610820929456203, coverage_judged: false, supported: 0.9914988420836631,
  supported_all: 0.947344211494698, collisions: 0, limits: 0, left_out_mm: 0, samples: 247836, failures: [], statement: '', ms: 183.7,
};
const GEODESIC_REFUSED = {
  mode: 'refuse', sound: false, inside: 0.9975820495321651, coverage: 0.9672968067842067, coverage_judged: true,
  supported: 0.9847217346489099, supported_all: 0.9785750951640452, collisions: 0, limits: 0, left_out_mm: 6458.955738639334,
  samples: 1856531, ms: 2538.9, failures: ['...'], statement: '...',
};

/** Rows as {key: [text, state]}. */
const rowsOf = (v) => Object.fromEntries(checkRows(v).map(([key, , text, state]) => [key, [text, state]]));

test('verifySection: the report\'s verify object, else null', () => {
  assert.equal(verifySection({ verify: VOXEL_REFUSED }), VOXEL_REFUSED);
  assert.equal(verifySection({ layers: 3 }), null, 'planar by default, or verify = off');
  assert.equal(verifySection(null), null);
  assert.equal(verifySection({ verify: 'x' }), null);
});

test('shareText: one decimal, more when a failing share would read as its bound', () => {
  assert.equal(shareText(0.96512, 0.99), '96.5 %');
  assert.equal(shareText(1, 0.99), '100.0 %');
  assert.equal(shareText(0.9914988, 0.99), '99.1 %');
  assert.equal(shareText(0.98996, 0.99), '98.996 %', 'not 99.0 %: it fails');
  assert.equal(shareText(0.98951, 0.99), '98.95 %');
  assert.equal(shareText(0.99, 0.99), '99.0 %', 'the bound itself passes');
  assert.equal(shareText(0.9675, 0.97), '96.8 %', 'reads below its bound already');
  assert.equal(shareText(0.96996, 0.97), '96.996 %');
  assert.equal(shareText(NaN, 0.99), '—');
  assert.equal(shareText(0.5), '50.0 %', 'no bound');
});

test('checkRows: a refused voxel program, every figure against its criterion', () => {
  const rows = checkRows(VOXEL_REFUSED);
  assert.deepEqual(rows.map(([key]) => key), ['inside', 'coverage', 'supported', 'collisions', 'limits', 'left_out', 'simulated']);
  for (const [key, label, text] of rows) {
    assert.equal(typeof label, 'string', key);
    assert.ok(text.length > 0, key);
  }
  assert.deepEqual(rowsOf(VOXEL_REFUSED), {
    inside: ['100.0 % (≥ 99 %)', 'pass'],
    coverage: ['94.0 % (≥ 97 %)', 'fail'],
    supported: ['96.5 % (≥ 99 %)', 'fail'],
    collisions: ['186 samples', 'fail'],
    limits: ['none', 'pass'],
    left_out: ['none', 'pass'],
    simulated: ['214,637 samples, 570 ms', ''],
  });
  // The rows that fail are the core's failures (its criteria are the page's).
  assert.equal(checkRows(VOXEL_REFUSED).filter((r) => r[3] === 'fail').length, VOXEL_REFUSED.failures.length);
  assert.deepEqual(SOUNDNESS_CRITERIA, { inside: 0.99, coverage: 0.97, supported: 0.99, surface_reached: 0.99 });
  // The report's own bounds win over the defaults (a report recorded with other criteria).
  const stricter = rowsOf({ ...MULTIDIR_SOUND, criteria: { inside: 0.99, coverage: 0.97, supported: 0.995 } });
  assert.deepEqual(stricter.supported, ['99.1 % (≥ 99.5 %)', 'fail']);
});

test('checkRows: coverage only where it is judged; left-out tool path in mm; missing figures as dashes', () => {
  const sound = rowsOf(MULTIDIR_SOUND);
  assert.equal(sound.coverage, undefined, 'multidir\'s sparse infill: coverage is not judged');
  assert.ok(Object.values(sound).every(([, state]) => state !== 'fail'));
  assert.deepEqual(sound.supported, ['99.1 % (≥ 99 %)', 'pass']);
  const geo = rowsOf(GEODESIC_REFUSED);
  assert.deepEqual(geo.left_out, ['6.46 m', 'fail']);
  assert.deepEqual(geo.coverage, ['96.7 % (≥ 97 %)', 'fail']);
  assert.deepEqual(geo.inside, ['99.8 % (≥ 99 %)', 'pass']);
  assert.deepEqual(geo.simulated, ['1,856,531 samples, 2.54 s', '']);
  assert.deepEqual(rowsOf({ ...MULTIDIR_SOUND, left_out_mm: 12.25, limits: 1, collisions: 1 }).left_out, ['12.3 mm', 'fail']);
  assert.deepEqual(rowsOf({ limits: 1, collisions: 1 }).limits, ['1 move', 'fail']);
  assert.deepEqual(rowsOf({}), {
    inside: ['—', ''], supported: ['—', ''], collisions: ['—', ''], limits: ['—', ''], left_out: ['—', ''], simulated: ['—', ''],
  });
  assert.deepEqual(checkRows(null), []);
});

test('checkRows: the programs made again after an unsound one, in order, the delivered one named', () => {
  const remedied = { ...MULTIDIR_SOUND, attempts: [
    { settings: 'voxel.smooth=10', why: 'nozzle collisions', sound: false, failures: ['3 tool-path samples ...'], ms: 900 },
    { settings: 'voxel.smooth=40', why: 'nozzle collisions', sound: true, failures: [], ms: 950 },
  ] };
  assert.deepEqual(rowsOf(remedied).attempts, ['voxel.smooth=10: not sound; voxel.smooth=40: sound (delivered)', '']);
  assert.equal(checkRows(remedied).at(-1)[0], 'attempts', 'after the figures');
  assert.equal(rowsOf(MULTIDIR_SOUND).attempts, undefined, 'none made again: no row');
  assert.equal(rowsOf({ ...MULTIDIR_SOUND, attempts: [] }).attempts, undefined);
  assert.equal(attemptsText([{ settings: 'geodesic.max_thickness_ratio=0.55', sound: false }]),
    'geodesic.max_thickness_ratio=0.55: not sound');
  assert.equal(attemptsText(null), '');
});

test('checkRows: the share of the surface printed, where the report has it', () => {
  const branches = rowsOf({ ...MULTIDIR_SOUND, surface_reached: 0.3151, surface_reach_mm: 0.9,
    criteria: { inside: 0.99, coverage: 0.97, supported: 0.99, surface_reached: 0.99 } });
  assert.deepEqual(branches.surface_reached, ['31.5 % (≥ 99 %)', 'fail']);
  assert.deepEqual(rowsOf({ ...MULTIDIR_SOUND, surface_reached: 1 }).surface_reached, ['100.0 % (≥ 99 %)', 'pass']);
  assert.deepEqual(checkRows({ ...VOXEL_REFUSED, surface_reached: 0.998 }).map(([key]) => key),
    ['inside', 'coverage', 'surface_reached', 'supported', 'collisions', 'limits', 'left_out', 'simulated']);
});

test('checkVerdict: sound, refused, written anyway; the done line', () => {
  assert.deepEqual(checkVerdict(MULTIDIR_SOUND), { state: 'sound', text: 'Sound: the simulated program meets every criterion.' });
  assert.equal(checkVerdict(VOXEL_REFUSED, { refused: true }).state, 'refused');
  assert.match(checkVerdict(VOXEL_REFUSED, { refused: true }).text, /no program was written/);
  assert.equal(checkVerdict({ ...VOXEL_REFUSED, mode: 'warn' }).state, 'warned');
  assert.match(checkVerdict({ ...VOXEL_REFUSED, mode: 'warn' }).text, /written anyway \(verify = warn\)/);
  assert.equal(checkVerdict(VOXEL_REFUSED).state, 'unsound', 'not sound, delivered without warn (a planar verify=refuse report, say)');
  assert.equal(checkVerdict(null), null);
  assert.equal(checkDoneSummary(MULTIDIR_SOUND), 'sound');
  assert.equal(checkDoneSummary({ ...VOXEL_REFUSED, mode: 'warn' }), 'not sound');
  assert.equal(checkDoneSummary(null), '');
  // The page's done line: the method's summary, then the verdict.
  const multidir = { part_count: 3, J_G_before: 720, J_G_after: 565.4 };
  assert.equal(doneSummary({ multidir, verify: MULTIDIR_SOUND }), '3 parts, J_G 720 → 565.4 mm² · sound');
  assert.equal(doneSummary({ verify: MULTIDIR_SOUND }), 'sound');
  assert.equal(doneSummary({ multidir }), '3 parts, J_G 720 → 565.4 mm²');
});

test('pointCloud: whole finite xyz triples, the buffer itself when all are finite', () => {
  const b = new Float32Array([0, 1, 2, 3, 4, 5]);
  assert.equal(pointCloud(b), b, 'no copy');
  assert.deepEqual([...pointCloud(new Float32Array([0, 1, 2, NaN, 4, 5, 6, 7, Infinity, 9, 10, 11]))], [0, 1, 2, 9, 10, 11]);
  assert.equal(pointCloud(null).length, 0);
  assert.equal(pointCloud(undefined).length, 0);
  assert.throws(() => pointCloud(new Float32Array(4), 'collisionPoints'), /collisionPoints has 4 values, not whole xyz triples/);
  assert.throws(() => pointCloud([0, 1, 2], 'unsupportedPoints'), /unsupportedPoints is not a Float32Array/);
});

test('failingPoints, hasCheckPoints, pointCountText', () => {
  const preview = { unsupportedPoints: new Float32Array([0, 0, 0, 1, 1, 1]), collisionPoints: new Float32Array([2, 2, 2]) };
  const p = failingPoints(preview);
  assert.equal(p.unsupported.count, 2);
  assert.equal(p.collisions.count, 1);
  assert.equal(p.collisions.positions, preview.collisionPoints);
  assert.deepEqual(failingPoints({}), { unsupported: { positions: new Float32Array(0), count: 0 }, collisions: { positions: new Float32Array(0), count: 0 } });
  assert.equal(hasCheckPoints(preview), true);
  assert.equal(hasCheckPoints({ collisionPoints: new Float32Array([1, 2, 3]) }), true);
  assert.equal(hasCheckPoints({ unsupportedPoints: new Float32Array(0), collisionPoints: new Float32Array(0) }), false);
  assert.equal(hasCheckPoints(null), false);
  assert.equal(pointCountText(186, 186), '186');
  assert.equal(pointCountText(4000, 26013), '4,000 of 26,013', 'the core keeps at most 4000 of each');
  assert.equal(pointCountText(870, NaN), '870');
});

test('the failing points\' colours differ from each other and from every tool-path feature colour', () => {
  const distance = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
  assert.deepEqual(FAILING_POINTS.map((f) => f.color), [UNSUPPORTED_COLOR, COLLISION_COLOR]);
  assert.ok(distance(UNSUPPORTED_COLOR, COLLISION_COLOR) > 200);
  for (const c of [UNSUPPORTED_COLOR, COLLISION_COLOR]) {
    for (const f of FEATURES) assert.ok(distance(c, f.color) > 80, `${c} vs ${f.name}`);
  }
});

test('ringSprite: a white disc in a dark ring, clear outside', () => {
  const n = 32;
  const px = ringSprite(n);
  assert.equal(px.length, n * n * 4);
  const at = (x, y) => [...px.subarray(4 * (y * n + x), 4 * (y * n + x) + 4)];
  assert.deepEqual(at(16, 16), [255, 255, 255, 255], 'centre');
  assert.deepEqual(at(16, 1), [16, 16, 16, 255], 'ring');
  assert.deepEqual(at(0, 0), [0, 0, 0, 0], 'corner');
});

test('CheckView: the two clouds in their colours, counts, toggle, bad buffers, dispose', () => {
  const preview = {
    unsupportedPoints: new Float32Array([0, 0, 0, 1, 1, 1, 2, 2, 2]),
    collisionPoints: new Float32Array([5, 5, 5]),
  };
  const v = new CheckView(preview, { collisions: 12 });
  const byName = Object.fromEntries(v.object.children.map((o) => [o.name, o]));
  assert.deepEqual(Object.keys(byName).sort(), ['check-collisions', 'check-unsupported']);
  const unsupported = byName['check-unsupported'];
  assert.equal(unsupported.isPoints, true);
  assert.equal(unsupported.geometry.getAttribute('position').count, 3);
  assert.equal(unsupported.geometry.getAttribute('position').array, preview.unsupportedPoints, 'the buffer as is');
  // The legend's colours as displayed (sRGB), as the other views give theirs.
  const hex = (c) => c.map((x) => x.toString(16).padStart(2, '0')).join('');
  assert.equal(unsupported.material.color.getHexString(), hex(UNSUPPORTED_COLOR));
  assert.equal(byName['check-collisions'].material.color.getHexString(), hex(COLLISION_COLOR));
  assert.equal(unsupported.material.depthTest, false, 'drawn over the part');
  assert.equal(unsupported.material.map, v.sprite);
  assert.deepEqual(v.stats(), { unsupported: 3, collisions: 1, collisionsTotal: 12, unsupportedDrawn: 3, collisionsDrawn: 1, visible: true });
  v.setVisible(false);
  assert.equal(unsupported.visible, false);
  assert.deepEqual([v.stats().unsupportedDrawn, v.stats().collisionsDrawn, v.stats().visible], [0, 0, false]);
  v.setVisible(true);
  assert.equal(v.stats().collisionsDrawn, 1);
  // A cloud without points stays hidden.
  const sound = new CheckView({ unsupportedPoints: new Float32Array([1, 2, 3]) }, { collisions: 0 });
  assert.equal(sound.clouds.collisions.visible, false);
  assert.equal(sound.stats().collisionsDrawn, 0);
  assert.throws(() => new CheckView({ unsupportedPoints: new Float32Array(5) }), /not whole xyz triples/);
  let disposed = 0;
  for (const o of [...v.object.children]) o.geometry.addEventListener('dispose', () => disposed++);
  let spriteDisposed = false;
  v.sprite.addEventListener('dispose', () => { spriteDisposed = true; });
  v.dispose();
  assert.equal(disposed, 2);
  assert.equal(spriteDisposed, true);
});

test('the check sits beside the methods in the registry, in their shape without a method\'s own data', () => {
  assert.deepEqual(EXTRAS, [check]);
  assert.ok(!METHODS.includes(check), 'not a choice of the method setting');
  for (const f of ['section', 'summaryRows', 'doneSummary', 'hasView']) assert.equal(typeof check.data[f], 'function', f);
  for (const f of ['show', 'wire', 'enable']) assert.equal(typeof check.panel[f], 'function', f);
  for (const f of ['build', 'setup', 'inspect']) assert.equal(typeof check.view[f], 'function', f);
  assert.equal(check.data.section({ verify: VOXEL_REFUSED }), VOXEL_REFUSED);
  assert.equal(check.data.section(null), null);
  assert.deepEqual(check.data.summaryRows(null), []);
  assert.equal(check.data.doneSummary(null), '');
});
