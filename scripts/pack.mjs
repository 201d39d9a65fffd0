// SPDX-License-Identifier: MIT
// npm run pack: the npm package omnislice-<version>.tgz (in build/), for vendors who install
// Omnislice instead of copying its folders. Staged in build/package with the served layout, so
// every relative import and the worker and wasm URLs (import.meta.url) resolve inside it:
//   web/omnislice-embed.js (+ placement.js, program-file.js)   the browser entry ("omnislice")
//   workers/                                                   facade, protocol, worker
//   wasm/omnislice.js, omnislice.mjs, omnislice.wasm           the engine (from build/wasm)
//   node/index.mjs, worker-thread.mjs                          "omnislice/node": worker_threads
// plus the TypeScript types. Needs the wasm build (npm run build:wasm).
//
//   node scripts/pack.mjs [--out DIR]      prints the tarball's path
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');

/** Files of the package: [path in the package, path in the repository]. */
export function packageFiles(wasmDir = path.join(ROOT, 'build', 'wasm')) {
  const files = [
    ['web/omnislice-embed.js', 'web/omnislice-embed.js'],
    ['web/omnislice-embed.d.ts', 'web/omnislice-embed.d.ts'],
    ['web/placement.js', 'web/placement.js'],
    ['web/program-file.js', 'web/program-file.js'],
    ['node/index.mjs', 'node/index.mjs'],
    ['node/index.d.ts', 'node/index.d.ts'],
    ['node/worker-thread.mjs', 'node/worker-thread.mjs'],
  ];
  for (const f of fs.readdirSync(path.join(ROOT, 'workers')).sort()) {
    if (f.endsWith('.js') || f.endsWith('.d.ts')) files.push([`workers/${f}`, `workers/${f}`]);
  }
  for (const f of ['omnislice.js', 'omnislice.d.ts', 'omnislice.mjs', 'omnislice.wasm']) {
    files.push([`wasm/${f}`, path.join(path.relative(ROOT, wasmDir), f)]);
  }
  return files;
}

/** The package's package.json. */
export function packageJson() {
  const root = JSON.parse(fs.readFileSync(path.join(ROOT, 'package.json'), 'utf8'));
  return {
    name: 'omnislice',
    version: root.version,
    description: root.description,
    license: root.license,
    type: 'module',
    engines: { node: '>=18' },
    exports: {
      '.': { types: './web/omnislice-embed.d.ts', default: './web/omnislice-embed.js' },
      './node': { types: './node/index.d.ts', default: './node/index.mjs' },
      './workers/engine.js': { types: './workers/engine.d.ts', default: './workers/engine.js' },
      './wasm/omnislice.js': { types: './wasm/omnislice.d.ts', default: './wasm/omnislice.js' },
      './package.json': './package.json',
    },
    types: './web/omnislice-embed.d.ts',
    sideEffects: ['./node/index.mjs'],
  };
}

/** Stage build/package and pack it into outDir; returns the tarball's path. */
export function pack({ outDir = path.join(ROOT, 'build'), wasmDir } = {}) {
  const stage = path.join(ROOT, 'build', 'package');
  fs.rmSync(stage, { recursive: true, force: true });
  for (const [to, from] of packageFiles(wasmDir)) {
    const src = path.resolve(ROOT, from);
    if (!fs.existsSync(src)) {
      throw new Error(`pack: ${from} is missing${from.includes('wasm') ? ' (npm run build:wasm)' : ''}`);
    }
    fs.mkdirSync(path.dirname(path.join(stage, to)), { recursive: true });
    fs.copyFileSync(src, path.join(stage, to));
  }
  fs.writeFileSync(path.join(stage, 'package.json'), `${JSON.stringify(packageJson(), null, 2)}\n`);
  fs.writeFileSync(path.join(stage, 'README.md'), [
    '# omnislice',
    '',
    'Multi-axis 3D-printing slicer (C++ core compiled to WebAssembly) for pages and Node.',
    '',
    '```js',
    "// Browser (serve the package's folders from your page's origin; bundlers keep import.meta.url):",
    "import { sliceFile } from 'omnislice';",
    '// Node 18+ (worker_threads):',
    "import { sliceFile, disposeSharedSlicer } from 'omnislice/node';",
    "const result = await sliceFile('part.stl', { layer_height: 0.2 });",
    'await disposeSharedSlicer();',
    '```',
    '',
    'API and settings: docs/EMBEDDING.md of the Omnislice repository.',
    '',
  ].join('\n'));
  fs.mkdirSync(outDir, { recursive: true });
  const out = execFileSync('npm', ['pack', '--pack-destination', path.resolve(outDir), '--json'], {
    cwd: stage, encoding: 'utf8', stdio: ['ignore', 'pipe', 'inherit'],
  });
  return path.join(path.resolve(outDir), JSON.parse(out)[0].filename);
}

if (process.argv[1] && path.resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  const at = process.argv.indexOf('--out');
  try {
    console.log(pack(at > 0 ? { outDir: process.argv[at + 1] } : {}));
  } catch (err) {
    console.error(err.message);
    process.exit(1);
  }
}
