// SPDX-License-Identifier: MIT
// Long loops on the page's main thread in blocks that give the thread back (shared by the
// tool-path preview and the voxel view's data preparation), and measured steps. Pure (no
// DOM, no three.js), so Node unit tests import it too.

/** Yield to the event loop (scheduler.yield where available, else a message round trip). */
export function yieldToEventLoop() {
  if (globalThis.scheduler && typeof globalThis.scheduler.yield === 'function') return globalThis.scheduler.yield();
  return new Promise((resolve) => {
    const { port1, port2 } = new MessageChannel();
    port1.onmessage = () => {
      port1.close();
      resolve();
    };
    port2.postMessage(null);
  });
}

/**
 * Runner run(n, fn) calling fn(from, to) over [0, n) in blocks; whenever a task has run budgetMs it
 * yields, so no single task runs long (the first blocks run before the JIT has optimised the
 * loops, so a time budget beats a fixed slice size). Each task is recorded as the performance
 * measure `measureName` (the end-to-end long-task checks read them); run.end() records the last.
 */
export function blockRunner(measureName, { budgetMs = 12, block = 4096 } = {}) {
  let t0 = performance.now();
  const run = async (n, fn) => {
    for (let from = 0; from < n; from += block) {
      fn(from, Math.min(n, from + block));
      if (performance.now() - t0 > budgetMs) {
        performance.measure(measureName, { start: t0, end: performance.now() });
        await yieldToEventLoop();
        t0 = performance.now();
      }
    }
  };
  run.end = () => performance.measure(measureName, { start: t0, end: performance.now() });
  return run;
}

/**
 * Run fn as one measured step (performance measure 'omnislice:<name>'), for the end-to-end
 * tests' long-task check; returns what fn returns.
 */
export function timed(name, fn) {
  const t0 = performance.now();
  try {
    return fn();
  } finally {
    performance.measure(`omnislice:${name}`, { start: t0, end: performance.now() });
  }
}
