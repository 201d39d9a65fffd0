// SPDX-License-Identifier: MIT
// Colour helpers of the page's views and legends (layers, parts, ramps). Pure: Node tests load it.

/** HSL (h in degrees, s and l in 0..1) -> [r, g, b] in 0..255. */
export function hslToRgb(h, s, l) {
  const a = s * Math.min(l, 1 - l);
  const f = (n) => {
    const k = (n + h / 30) % 12;
    return Math.round(255 * (l - a * Math.max(-1, Math.min(k - 3, 9 - k, 1))));
  };
  return [f(0), f(8), f(4)];
}

/** CSS text of a 0..255 RGB colour: 'rgb(r,g,b)'. */
export function rgbCss(color) {
  return `rgb(${color.join(',')})`;
}
