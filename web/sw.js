// SPDX-License-Identifier: MIT
// The app's service worker (registered by main.js, scope /): after the first visit the page loads
// and slices with the network gone.
// - install: every file the app and its workers load (APP_FILES: the page, its modules, the
//   workers, the wasm engine, three.js, the demo models, the manifest and icons) goes into one
//   cache, so a visit that ended before the worker took control is enough.
// - fetch (same-origin GET): the network first, so an online page always runs the files the
//   server has now and refreshes the cache with them; the cache when the network fails.
// - activate: older caches of this app are deleted, and open pages are taken over.
// tests/js/offline.test.mjs checks APP_FILES against the served tree (a file added to web/ or
// workers/ must be listed); tests/e2e/offline.test.mjs reloads the page offline and slices.
const CACHE = 'omnislice-app-v1';

const APP_FILES = [
  '/',
  '/index.html',
  '/styles.css',
  '/manifest.webmanifest',
  '/icons/icon-192.png',
  '/icons/icon-512.png',
  '/block-runner.js',
  '/colors.js',
  '/demo-models.js',
  '/embed.html',
  '/embed.js',
  '/format.js',
  '/machine-kinematics.js',
  '/machine-panel.js',
  '/machine-view.js',
  '/main.js',
  '/methods/auto-data.js',
  '/methods/auto.js',
  '/methods/check-data.js',
  '/methods/check-panel.js',
  '/methods/check-view.js',
  '/methods/check.js',
  '/methods/geodesic-data.js',
  '/methods/geodesic-panel.js',
  '/methods/geodesic-view.js',
  '/methods/geodesic.js',
  '/methods/index.js',
  '/methods/isoplanar-data.js',
  '/methods/isoplanar-panel.js',
  '/methods/machine-needs.js',
  '/methods/multidir-data.js',
  '/methods/multidir-panel.js',
  '/methods/multidir-view.js',
  '/methods/multidir.js',
  '/methods/planar-data.js',
  '/methods/planar-panel.js',
  '/methods/planar.js',
  '/methods/surface.js',
  '/methods/voxel-data.js',
  '/methods/voxel-panel.js',
  '/methods/voxel-view.js',
  '/methods/voxel.js',
  '/model-panel.js',
  '/models/demo-arms.obj',
  '/models/demo-overhang.stl',
  '/models/demo-saddle.obj',
  '/models/demo-tree.obj',
  '/omnislice-embed.js',
  '/page-api.js',
  '/panel-dom.js',
  '/placement.js',
  '/preview.js',
  '/program-file.js',
  '/settings-fields.js',
  '/settings-panel.js',
  '/status-panel.js',
  '/viewer.js',
  '/workers/auto-pool.js',
  '/workers/engine.js',
  '/workers/protocol.js',
  '/workers/slicer-worker.js',
  '/wasm/omnislice.js',
  '/wasm/omnislice.mjs',
  '/wasm/omnislice.wasm',
  '/vendor/three/build/three.module.js',
  '/vendor/three/build/three.core.js',
  '/vendor/three/examples/jsm/controls/OrbitControls.js',
];

self.addEventListener('install', (event) => {
  // cache: 'reload' bypasses the HTTP cache, so the app's cache holds what the server has now.
  event.waitUntil(caches.open(CACHE)
    .then((cache) => cache.addAll(APP_FILES.map((url) => new Request(url, { cache: 'reload' }))))
    .then(() => self.skipWaiting()));
});

self.addEventListener('activate', (event) => {
  event.waitUntil(caches.keys()
    .then((keys) => Promise.all(keys
      .filter((key) => key.startsWith('omnislice-app-') && key !== CACHE)
      .map((key) => caches.delete(key))))
    .then(() => self.clients.claim()));
});

self.addEventListener('fetch', (event) => {
  const request = event.request;
  if (request.method !== 'GET' || new URL(request.url).origin !== self.location.origin) return;
  event.respondWith(fetch(request)
    .then((response) => {
      if (response.ok && response.type === 'basic') {
        const copy = response.clone();
        event.waitUntil(caches.open(CACHE).then((cache) => cache.put(request, copy)));
      }
      return response;
    })
    .catch(async () => {
      const hit = await caches.match(request, { ignoreSearch: true });
      if (hit) return hit;
      // A page (navigation) of the app: the app itself.
      if (request.mode === 'navigate') {
        const page = await caches.match('/');
        if (page) return page;
      }
      return Response.error();
    }));
});
