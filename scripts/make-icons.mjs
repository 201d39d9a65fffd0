// SPDX-License-Identifier: MIT
// The app's icons (web/icons/icon-192.png, icon-512.png), drawn here: curved layers printed on a
// tilted platform under a nozzle, on the page's dark panel colour. Deterministic (the test
// regenerates them and compares the bytes). PNG written with Node's zlib, no image library.
//
//   node scripts/make-icons.mjs          (writes the two files)
import fs from 'node:fs';
import path from 'node:path';
import zlib from 'node:zlib';
import { fileURLToPath } from 'node:url';

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
export const ICON_SIZES = [192, 512];

const CRC_TABLE = Array.from({ length: 256 }, (_, n) => {
  let c = n;
  for (let k = 0; k < 8; k++) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
  return c >>> 0;
});
function crc32(bytes) {
  let c = 0xffffffff;
  for (const b of bytes) c = CRC_TABLE[(c ^ b) & 0xff] ^ (c >>> 8);
  return (c ^ 0xffffffff) >>> 0;
}
function chunk(type, data) {
  const out = Buffer.alloc(12 + data.length);
  out.writeUInt32BE(data.length, 0);
  out.write(type, 4, 'ascii');
  data.copy(out, 8);
  out.writeUInt32BE(crc32(out.subarray(4, 8 + data.length)), 8 + data.length);
  return out;
}

/** PNG bytes of an RGBA image (rows top to bottom). */
export function encodePng(width, height, rgba) {
  const raw = Buffer.alloc((4 * width + 1) * height);
  for (let y = 0; y < height; y++) {
    raw[y * (4 * width + 1)] = 0;  // filter: none
    rgba.copy(raw, y * (4 * width + 1) + 1, 4 * width * y, 4 * width * (y + 1));
  }
  const header = Buffer.alloc(13);
  header.writeUInt32BE(width, 0);
  header.writeUInt32BE(height, 4);
  header.set([8, 6, 0, 0, 0], 8);  // 8 bits, RGBA
  return Buffer.concat([
    Buffer.from([0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a]),
    chunk('IHDR', header),
    chunk('IDAT', zlib.deflateSync(raw, { level: 9 })),
    chunk('IEND', Buffer.alloc(0)),
  ]);
}

/** The icon at size x size pixels, RGBA; 4 x 4 samples per pixel. */
export function drawIcon(size) {
  const rgba = Buffer.alloc(4 * size * size);
  const bg = [0x1b, 0x1f, 0x27], layer = [[0x4f, 0xa3, 0xe0], [0x6f, 0xc2, 0x8b], [0xf0, 0xa2, 0x3b]];
  const nozzle = [0xe8, 0xe8, 0xe8];
  const tilt = -0.35;  // the platform's tilt (rad)
  const ct = Math.cos(tilt), st = Math.sin(tilt);
  // Colour of a point in unit coordinates (x right, y down, [0, 1]); null = transparent.
  const shade = (x, y) => {
    const r = 0.18;  // rounded square
    const dx = Math.max(Math.abs(x - 0.5) - (0.5 - r), 0), dy = Math.max(Math.abs(y - 0.5) - (0.5 - r), 0);
    if (dx * dx + dy * dy > r * r) return null;
    // Nozzle: a trapezoid from the top down to its tip at (0.5, 0.36).
    if (y > 0.1 && y < 0.36 && Math.abs(x - 0.5) < 0.03 + 0.09 * (0.36 - y) / 0.26) return nozzle;
    // Platform frame: u along the tilted platform, v up from it, centred below the nozzle.
    const px = x - 0.5, py = y - 0.74;
    const u = px * ct + py * st, v = -(-px * st + py * ct);
    if (v > -0.035 && v < 0 && Math.abs(u) < 0.36) return [0x9a, 0xa4, 0xb1];
    // Curved layers: arcs about a centre below the platform, each band a layer.
    const rr = Math.hypot(u, v + 0.55);
    for (let k = 0; k < 3; k++) {
      const r0 = 0.565 + 0.075 * k;
      if (rr > r0 && rr < r0 + 0.06 && v > 0 && Math.abs(u) < 0.3 - 0.06 * k) return layer[k];
    }
    return bg;
  };
  const n = 4;
  for (let py = 0; py < size; py++) {
    for (let px = 0; px < size; px++) {
      let r = 0, g = 0, b = 0, a = 0;
      for (let sy = 0; sy < n; sy++) {
        for (let sx = 0; sx < n; sx++) {
          const c = shade((px + (sx + 0.5) / n) / size, (py + (sy + 0.5) / n) / size);
          if (!c) continue;
          r += c[0]; g += c[1]; b += c[2]; a += 1;
        }
      }
      const o = 4 * (py * size + px);
      if (a) {
        rgba[o] = Math.round(r / a);
        rgba[o + 1] = Math.round(g / a);
        rgba[o + 2] = Math.round(b / a);
      }
      rgba[o + 3] = Math.round((255 * a) / (n * n));
    }
  }
  return rgba;
}

export function iconPng(size) { return encodePng(size, size, drawIcon(size)); }

if (process.argv[1] && path.resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  const dir = path.join(ROOT, 'web', 'icons');
  fs.mkdirSync(dir, { recursive: true });
  for (const size of ICON_SIZES) {
    const file = path.join(dir, `icon-${size}.png`);
    fs.writeFileSync(file, iconPng(size));
    console.log(`${path.relative(ROOT, file)}: ${fs.statSync(file).size} bytes`);
  }
}
