// SPDX-License-Identifier: MIT
// A Node worker thread that runs the browser's slicer worker (workers/slicer-worker.js) unchanged:
// the few worker globals it uses (self, postMessage, onmessage, location) are provided over
// worker_threads' parentPort, then the worker module is imported (its URL in workerData).
import { parentPort, workerData } from 'node:worker_threads';

const listeners = [];
globalThis.self = globalThis;
Object.defineProperty(globalThis, 'location', { value: { href: workerData.url }, configurable: true });
globalThis.postMessage = (message, transfer = []) => parentPort.postMessage(message, transfer);
globalThis.addEventListener = (type, listener) => {
  if (type === 'message') listeners.push(listener);
};
function dispatch(data) {
  const event = { data };
  if (typeof globalThis.onmessage === 'function') globalThis.onmessage(event);
  for (const listener of listeners) listener(event);
}
// A browser queues the messages that arrive before the worker's script has run; so does this
// thread, until the worker module is evaluated.
let queued = [];
parentPort.on('message', (data) => {
  if (queued) queued.push(data);
  else dispatch(data);
});
await import(workerData.url);
const early = queued;
queued = null;
for (const data of early) dispatch(data);
