// SPDX-License-Identifier: MIT
// method = auto over a pool of workers: the candidates of the core's plan (planAuto) each sliced
// on its own, as many at once as there are workers, then the core's choice (chooseAuto) asked
// until it names the delivered one. The rule is the core's (core/pipeline/auto_choice.h); this
// module only schedules. It knows no worker API: the caller gives `run` and `choose` (the engine
// facade, engine.js, with its workers in a page; scripts/bench.mjs with worker_threads in Node).
//
// The delivered program is the one the core's own method = auto makes in threads (every candidate
// checked, none stopped early; an unsound one that could still win made again with every attempt,
// in order), whatever the number of workers and the order they finish in.

import { OmnisliceError } from '../wasm/omnislice.js';

const now = () => (globalThis.performance ? performance.now() : Date.now());

/**
 * @param {object} options
 * @param {{candidates: {method: string, settings: object}[], rerun_settings: object}} options.plan
 * @param {object} options.settings   the user's settings (a candidate's: these changed by its own)
 * @param {number} options.size       workers (lanes) to use, >= 1
 * @param {(lane: number, k: number, settings: object, onProgress: Function) => Promise<object>} options.run
 *   slice candidate k in lane `lane` (0 .. size-1, one job per lane at a time); resolves with a
 *   result that has `report` (object), rejects with an error that has `code`
 * @param {(candidates: object[]) => Promise<object>} options.choose  the core's chooseAuto
 * @param {(p: {stage: string, fraction: number, candidate?: string}) => void} [options.onProgress]
 *   each candidate's progress with its method as `candidate`, and stage 'auto' (fraction: the
 *   share of candidates done)
 * @param {AbortSignal} [options.signal]
 * @returns {Promise<{decision: object, result: object|null, results: (object|null)[], ms: number}>}
 *   results: every candidate's, in the plan's order (null where it failed)
 */
export async function runAutoPool({ plan, settings, size, run, choose, onProgress, signal }) {
  const cands = plan.candidates;
  const n = cands.length;
  const entries = new Array(n);
  const results = new Array(n).fill(null);
  const start = now();
  const tell = (p) => {
    if (onProgress) {
      try { onProgress(p); } catch { /* a caller bug does not stop the slice */ }
    }
  };
  const runOne = async (lane, k, full) => {
    const method = cands[k].method;
    const changes = full ? { ...cands[k].settings, ...plan.rerun_settings } : cands[k].settings;
    const t0 = now();
    try {
      const r = await run(lane, k, { ...settings, ...changes }, (p) => tell({ ...p, candidate: method }));
      results[k] = r;
      entries[k] = { method, status: 'ok', message: '', ms: now() - t0, full, report: r.report };
    } catch (e) {
      // A cancel (the caller's signal) stops all; any other failure is this candidate's.
      if ((signal && signal.aborted) || (e && e.code === 'cancelled')) throw e;
      results[k] = null;
      entries[k] = {
        method, status: (e && e.code) || 'internal', message: String((e && e.message) || e), ms: now() - t0,
        full, report: null,
      };
    }
  };
  // The plan lists the cheapest first: the dearest start first, so the last to finish is short.
  const queue = [...cands.keys()].reverse();
  let done = 0;
  tell({ stage: 'auto', fraction: 0 });
  const lanes = [];
  for (let lane = 0; lane < Math.max(1, Math.min(size, n)); lane++) {
    lanes.push((async () => {
      for (let k = queue.shift(); k !== undefined; k = queue.shift()) {
        await runOne(lane, k, false);
        tell({ stage: 'auto', fraction: ++done / n });
      }
    })());
  }
  // Every lane ends before a failure is passed on (no job left running behind the caller's back).
  const settled = await Promise.allSettled(lanes);
  const failure = settled.find((s) => s.status === 'rejected');
  if (failure) throw failure.reason;
  for (let rounds = 0; ; rounds++) {
    const decision = await choose(entries);
    if (decision.rerun === undefined) {
      return { decision, result: decision.chosen >= 0 ? results[decision.chosen] : null, results, ms: now() - start };
    }
    if (rounds >= n) throw new OmnisliceError('internal', 'method = auto: the choice asked again and again');
    await runOne(0, decision.rerun, true);
  }
}
