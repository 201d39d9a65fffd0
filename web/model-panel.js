// SPDX-License-Identifier: MIT
// The model panel's figures of the loaded mesh (info from the engine: faces, closed, the placed
// part's size, repairs) and its notes (errors and warnings).
import { describeList } from './format.js';
import { byTestId as $, noteItem } from './panel-dom.js';

/** The size [dx, dy, dz] of a bounding box ({min, max} or [min, max]), or null. */
function bboxSize(bbox) {
  if (!bbox) return null;
  const min = bbox.min || bbox[0];
  const max = bbox.max || bbox[1];
  if (!Array.isArray(min) || !Array.isArray(max)) return null;
  return max.map((x, i) => x - min[i]);
}

/** Show the mesh info of the model `name` (null info: dashes). */
export function showInfo(name, info) {
  $('model-name').textContent = name;
  $('info-faces').textContent = info && info.faces !== undefined ? Number(info.faces).toLocaleString('en') : '—';
  $('info-closed').textContent = info && info.closed !== undefined ? (info.closed ? 'yes' : 'no') : '—';
  // The placed part's box (part frame), else the file's.
  const size = bboxSize(info && (info.placed_bbox || info.bbox));
  $('info-size').textContent = size ? size.map((x) => x.toFixed(1)).join(' × ') : '—';
  const repairs = describeList(info && info.repairs);
  const filled = info && info.repair && info.repair.filled_faces > 0 ? ' (filled holes drawn in amber)' : '';
  $('info-repairs').textContent = repairs.length ? repairs.join(', ') + filled : 'none';
  $('info-warnings').replaceChildren(...[['error', info && info.errors], ['warning', info && info.warnings]]
    .flatMap(([kind, list]) => describeList(list).map((text) => noteItem(kind, text))));
}
