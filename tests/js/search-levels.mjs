// SPDX-License-Identifier: MIT
// What the search-level progress events of a multidir slice keep (core/common/progress.h
// SearchLevelProgress, workers/protocol.js SEARCH_LINES), checked against the slice's report; shared
// by the wasm test in Node and the worker protocol test in Chromium.
import assert from 'node:assert/strict';
import { SEARCH_LINES } from '../../workers/protocol.js';

/**
 * Check the progress events of one multidir slice (beam scheme, 5dof) against report.multidir:
 * every `search` is well formed and comes with stage 'decompose'; the lines run greedy,
 * constrained, one beam line per restart run (search.restarts_run, at most `restarts`, fewer only
 * when J_G after <= 0.1 mm^2), then the chosen sequence; each search line counts its levels 0, 1, 2, ...
 * with a nonincreasing J_G; their levels >= 1 number search.levels; the chosen levels are 0..N with
 * exactly search.J_G_per_level.
 * @param {{stage: string, fraction: number, search?: object}[]} events every progress event
 * @param {object} multidir report.multidir of the slice
 * @param {number} [restarts] the slice's multidir.restarts (default 3)
 * @returns {{levels: object[], chosen: number[]}} the search events and the chosen J_G values
 */
export function checkSearchLevels(events, multidir, restarts = 3) {
  const levels = events.filter((p) => p.search).map((p) => {
    assert.equal(p.stage, 'decompose', `a search level comes with stage decompose: ${JSON.stringify(p)}`);
    return p.search;
  });
  assert.ok(levels.length > 0, 'search-level events reached JS');
  for (const s of levels) {
    assert.ok(SEARCH_LINES.includes(s.line), `line ${s.line}`);
    assert.ok(Number.isInteger(s.level) && s.level >= 0, `level ${s.level}`);
    assert.ok(Number.isFinite(s.J_G) && s.J_G >= 0, `J_G ${s.J_G}`);
    assert.ok(Number.isInteger(s.beams) && s.beams >= 0, `beams ${s.beams}`);
  }
  // Runs of one line each, in the beam scheme's order.
  const runs = [];
  for (const s of levels) {
    if (s.level === 0) runs.push({ line: s.line, list: [] });
    assert.ok(runs.length > 0 && runs[runs.length - 1].line === s.line, `a ${s.line} level ${s.level} outside its line's run`);
    runs[runs.length - 1].list.push(s);
  }
  const run = multidir.search.restarts_run;
  assert.ok(Number.isInteger(run) && run >= 1 && run <= restarts, `restarts_run ${run} of ${restarts}`);
  if (run < restarts) assert.ok(multidir.J_G_after <= 0.1 + 1e-9, `restarts stopped early at J_G ${multidir.J_G_after}`);
  assert.deepEqual(runs.map((r) => r.line), ['greedy', 'constrained', ...Array(run).fill('beam'), 'chosen']);
  for (const { line, list } of runs) {
    list.forEach((s, k) => assert.equal(s.level, k, `${line}: level ${s.level} at position ${k}`));
    assert.equal(list[0].J_G, multidir.J_G_before, `${line} starts at J_G before`);
    if (line === 'chosen') continue;
    for (let k = 1; k < list.length; k++) {
      assert.ok(list[k].J_G <= list[k - 1].J_G, `${line}: J_G rose from ${list[k - 1].J_G} to ${list[k].J_G} at level ${k}`);
    }
    assert.equal(list[list.length - 1].beams, 0, `${line} ends with no live beam`);
  }
  const searched = levels.filter((s) => s.line !== 'chosen' && s.level >= 1).length;
  assert.equal(searched, multidir.search.levels, 'one event per level the search expanded');
  const chosen = runs[runs.length - 1].list.map((s) => s.J_G);
  assert.deepEqual(chosen, multidir.search.J_G_per_level, 'the chosen levels are the report\'s J_G per level');
  return { levels, chosen };
}
