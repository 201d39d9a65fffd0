// SPDX-License-Identifier: MIT
// The geodesic method in the wasm module (Node) against the native CLI, on the demo tree at a
// coarse tet size (about 20k tets) and a 45° nozzle angle: the same tets, layers, IGDS, tree and
// sequence, the same retractions and collision verdict for all three traversals, the same floats
// (max geodesic distance, air moves, tet quality, overhang ratio per layer; overhang angles to
// 1e-12). Then what the page reads:
// the preview buffers pass the page's checks, the air moves the page draws (transitions off the
// tree) are exactly the report's retractions with its air-move length, the field spans the
// report's maximum distance, and the overhang chart has one point per layer.
// Skipped (not under CI) without the wasm build or the native CLI.
import { before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { CI, NATIVE_CLI, REPO, loadShipped, wasmUnavailable } from './wasm-support.mjs';
import { TRAVERSALS, airMoves, checkGeodesicBuffers, overhangChartGeometry } from '../../web/methods/geodesic-data.js';

const why = wasmUnavailable();
if (why && CI) throw new Error(`wasm tests cannot run under CI: ${why}`);
const nativeWhy = fs.existsSync(NATIVE_CLI) ? null : `native CLI ${NATIVE_CLI} missing (scripts/build.sh native)`;
if (!why && nativeWhy && CI) throw new Error(nativeWhy);

const MODEL = path.join(REPO, 'web', 'models', 'demo-tree.obj');
const SETTINGS = {
  method: 'geodesic', machine: 'table5', nozzle: 0.8, 'geodesic.interval_mm': 1.2, 'geodesic.tet_size_mm': 1.6,
  'geodesic.nozzle_angle_deg': 45,
};

/** |a - b| within rel * max(1, |b|), with a message. */
function close(actual, expected, rel, what) {
  const tol = rel * Math.max(1, Math.abs(expected));
  assert.ok(Math.abs(actual - expected) <= tol, `${what}: wasm ${actual} vs native ${expected} (tol ${tol})`);
}

describe('geodesic method: wasm (Node) vs native CLI', { skip: why || nativeWhy ? `skipped: ${why || nativeWhy}` : false }, () => {
  let wasm;
  let native;
  before(async () => {
    const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'omnislice-geo-'));
    try {
      const args = ['slice', MODEL, '-o', path.join(tmp, 'tree.gcode'), '--report', path.join(tmp, 'report.json')];
      for (const [k, v] of Object.entries(SETTINGS)) args.push('--set', `${k}=${v}`);
      execFileSync(NATIVE_CLI, args, { stdio: ['ignore', 'pipe', 'pipe'] });
      native = JSON.parse(fs.readFileSync(path.join(tmp, 'report.json'), 'utf8'));
    } finally {
      fs.rmSync(tmp, { recursive: true, force: true });
    }
    const { module: m } = await loadShipped();
    wasm = m.slice(fs.readFileSync(MODEL), 'demo-tree.obj', SETTINGS);
  });

  test('the same tets, layers, IGDS, tree and sequences', (t) => {
    const a = wasm.report.geodesic;
    const b = native.geodesic;
    assert.ok(a && b, 'both reports have a geodesic object');
    for (const k of ['tets', 'vertices', 'layers', 'printed_layers', 'igds', 'sequence', 'retractions', 'collision_free', 'paths']) {
      assert.deepEqual(a[k], b[k], k);
    }
    for (const k of ['nodes', 'edges', 'is_tree', 'branch_points', 'merges']) assert.equal(a.tree[k], b.tree[k], `tree.${k}`);
    for (const name of TRAVERSALS) {
      for (const k of ['retractions', 'collision_free', 'colliding_nodes', 'colliding_lower_bound', 'unavoidable_nodes', 'criterion2_relaxed']) {
        assert.equal(a.traversals[name][k], b.traversals[name][k], `${name}.${k}`);
      }
    }
    // The same bits: the tet mesher's order is total (its snapping sort broke ties differently
    // in libstdc++ and libc++, and the wasm mesh then differed by 0.1 mm^3 of 6200; the fields by
    // ~1e-5 relative), and every later stage uses only correctly rounded arithmetic.
    assert.equal(a.max_geodesic_mm, b.max_geodesic_mm, 'max_geodesic_mm');
    assert.equal(a.air_move_mm, b.air_move_mm, 'air_move_mm');
    for (const name of TRAVERSALS) assert.equal(a.traversals[name].air_move_mm, b.traversals[name].air_move_mm, `${name}.air_move_mm`);
    // The per-layer overhang averages agree to the last few bits (not found why: their terms use
    // only det::atan2 and arithmetic); the ratios exactly.
    assert.equal(a.overhang_avg_deg.length, b.overhang_avg_deg.length);
    a.overhang_avg_deg.forEach((v, l) => close(v, b.overhang_avg_deg[l], 1e-12, `overhang_avg_deg[${l}]`));
    assert.deepEqual(a.overhang_ratio, b.overhang_ratio, 'overhang_ratio');
    assert.equal(a.triangles, b.triangles, 'IGDS triangles');
    assert.deepEqual(a.tet_quality, b.tet_quality, 'tet_quality');
    assert.equal(wasm.report.layers, native.layers, 'report.layers');
    // The demo's point: A3 collision-free with fewer retractions than LPT.
    assert.equal(b.traversals.A3.collision_free, true, 'A3 collision-free');
    assert.ok(b.traversals.A3.retractions < b.traversals.LPT.retractions, `A3 ${b.traversals.A3.retractions} < LPT ${b.traversals.LPT.retractions}`);
    t.diagnostic(`${b.tets} tets, ${b.layers} layers, ${b.igds} IGDS; LPT ${b.traversals.LPT.retractions} / DPT ${b.traversals.DPT.retractions}`
      + ` (${b.traversals.DPT.collision_free ? 'free' : 'collides'}) / A3 ${b.traversals.A3.retractions} retractions`);
  });

  test('the page\'s reading of the preview: checks pass, air moves are the retractions, chart per layer', () => {
    const g = wasm.report.geodesic;
    const p = wasm.preview;
    const c = checkGeodesicBuffers(p);
    assert.equal(c.nodes, g.igds, 'one tree node per IGDS');
    assert.equal(c.edges, g.tree.edges);
    assert.ok(c.layerCount <= g.layers);
    assert.ok(c.fieldTriangles > 0 && c.fieldVertices > 0);
    const moves = airMoves(p.nodePositions, p.treeEdges, p.sequence);
    assert.equal(moves.count, g.retractions, 'the page draws one air move per retraction');
    close(moves.lengthMm, g.air_move_mm, 1e-4, 'drawn air-move length (float32 centroids)');
    let max = 0;
    for (const v of p.fieldValues) max = Math.max(max, v);
    assert.ok(max <= g.max_geodesic_mm * (1 + 1e-5) && max >= 0.9 * g.max_geodesic_mm, `field max ${max} vs ${g.max_geodesic_mm}`);
    const chart = overhangChartGeometry(g);
    assert.equal(chart.layers, g.layers);
    assert.equal(chart.points.length, g.layers, 'one chart point per layer');
    assert.equal(g.iso_values_mm.length, g.layers);
    // The IGDS surfaces: every layer index within the report's layers.
    let top = 0;
    for (const l of p.surfaceLayers) top = Math.max(top, l);
    assert.ok(p.surfaceLayers.length > 0 && top < g.layers);
  });
});
