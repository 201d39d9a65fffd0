// SPDX-License-Identifier: MIT
// The iframe API (web/embed.html), for portals that frame Omnislice instead of hosting its files:
//   parent -> frame  {type: 'slice', id, name, bytes: ArrayBuffer, settings}   (bytes transferred)
//                    {type: 'cancel', id}
//   frame -> parent  {type: 'ready'} once it takes work (posted to each allowed origin, so only an
//                    allowed parent receives it)
//                    {type: 'progress', id, stage, fraction}
//                    {type: 'result', id, fileName, programExtension, programBytes, report}
//                      (programBytes: a Uint8Array whose buffer is transferred)
//                    {type: 'error', id, code, message}: the engine's error codes, and
//                      'origin_not_allowed' for a parent whose origin the host has not listed
// Allowed origins: /embed-origins.json ({"origins": [...]}), which scripts/serve.mjs answers from
// OMNISLICE_EMBED_ORIGINS and another host serves as a file; missing or unreadable: none.
import { sliceFile } from './omnislice-embed.js';

const ORIGINS_URL = '/embed-origins.json';

async function loadAllowedOrigins() {
  try {
    const response = await fetch(ORIGINS_URL, { cache: 'no-store' });
    if (!response.ok) return [];
    const config = await response.json();
    return Array.isArray(config.origins) ? config.origins.filter((o) => typeof o === 'string') : [];
  } catch {
    return [];
  }
}

const allowedOrigins = loadAllowedOrigins();
const jobs = new Map();  // id -> AbortController of a running slice

// Listening from the start: a request that arrives before the origins are known waits for them.
window.addEventListener('message', async (event) => {
  const message = event.data;
  if (!message || typeof message !== 'object' || !event.source) return;
  const id = message.id ?? null;
  const reply = (data, transfer = []) => event.source.postMessage(data, { targetOrigin: event.origin, transfer });
  const fail = (code, text) => reply({ type: 'error', id, code, message: text });
  if (!(await allowedOrigins).includes(event.origin)) {
    fail('origin_not_allowed', `${event.origin} is not an origin this Omnislice serves (${ORIGINS_URL})`);
    return;
  }
  if (message.type === 'cancel') {
    jobs.get(id)?.abort();
    return;
  }
  if (message.type !== 'slice') {
    fail('invalid_option', `unknown request type "${message.type}" (slice, cancel)`);
    return;
  }
  const bytes = message.bytes;
  if (typeof message.name !== 'string' || !(bytes instanceof ArrayBuffer || ArrayBuffer.isView(bytes))) {
    fail('invalid_option', 'a slice request needs name (a file name) and bytes (an ArrayBuffer)');
    return;
  }
  if (message.settings !== undefined && (typeof message.settings !== 'object' || message.settings === null)) {
    fail('invalid_option', 'settings must be an object of setting keys');
    return;
  }
  if (jobs.has(id)) {
    fail('invalid_option', `a slice with id ${id} is already running`);
    return;
  }
  const abort = new AbortController();
  jobs.set(id, abort);
  try {
    const result = await sliceFile({ name: message.name, bytes }, message.settings || {}, {
      signal: abort.signal,
      onProgress: ({ stage, fraction }) => reply({ type: 'progress', id, stage, fraction }),
    });
    const program = result.programBytes;
    reply({
      type: 'result', id, fileName: result.fileName, programExtension: result.programExtension,
      programBytes: program, report: result.report,
    }, [program.buffer]);
  } catch (err) {
    fail(err.code || 'internal', err.message || String(err));
  } finally {
    jobs.delete(id);
  }
});

allowedOrigins.then((origins) => {
  if (window.parent === window) return;
  for (const origin of origins) window.parent.postMessage({ type: 'ready' }, origin);
});
