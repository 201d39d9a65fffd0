// SPDX-License-Identifier: MIT
// method = auto in the registry (index.js): not a method of its own but the choice among them.
// The result is the chosen method's (its sections and views show as usual); the group
// 'auto-report' adds the candidates side by side (auto-data.js): verdict, supported, collisions,
// support, time, how long each took, the chosen one marked; "use" shows another candidate's
// program (held when sound and made in the pool of workers, else sliced again; an undoable
// settings edit of the method).
import { byTestId as $, fillFigureList } from '../panel-dom.js';
import { SetSettingCommand } from '../settings-panel.js';
import { featureCss } from '../preview.js';
import { AUTO_STAGE_WEIGHTS, autoDoneSummary, autoSection, autoSummaryRows, candidateRows, thumbnailLines } from './auto-data.js';

const THUMB_W = 84, THUMB_H = 60;

/**
 * A small picture of a candidate's program (auto-data.js thumbnailLines) on a canvas: its beads by
 * feature colour, where its check fails on top (orange unsupported, red collisions). Null when its
 * result is not held (a candidate made one after another in a single worker).
 */
function thumbnail(result, method) {
  const t = result && thumbnailLines(result.preview, THUMB_W, THUMB_H);
  if (!t) return null;
  const canvas = document.createElement('canvas');
  canvas.width = THUMB_W;
  canvas.height = THUMB_H;
  canvas.className = 'auto-thumb';
  canvas.dataset.testid = `auto-thumb-${method}`;
  canvas.dataset.lines = String(t.features.length);
  canvas.title = `${method}: its program seen from the front right; orange: unsupported, red: collisions`;
  const g = canvas.getContext('2d');
  if (!g) return canvas;
  g.lineWidth = 0.6;
  for (const code of new Set(t.features)) {
    g.strokeStyle = featureCss(code);
    g.beginPath();
    for (let k = 0; k < t.features.length; k++) {
      if (t.features[k] !== code) continue;
      g.moveTo(t.lines[4 * k], t.lines[4 * k + 1]);
      g.lineTo(t.lines[4 * k + 2], t.lines[4 * k + 3]);
    }
    g.stroke();
  }
  for (const [points, colour] of [[t.unsupported, '#ff9f1c'], [t.collisions, '#ff2d2d']]) {
    g.fillStyle = colour;
    for (let i = 0; i < points.length; i += 2) g.fillRect(points[i] - 1, points[i + 1] - 1, 2, 2);
  }
  return canvas;
}

/**
 * Another candidate's program (an undoable settings edit of the method). A sound one made in the
 * pool of workers is held by the result (result.candidates) and shown at once: it is the program
 * that method alone makes (a sound first program is delivered as made). Others slice again.
 */
async function useMethod(app, method) {
  if (app.busy || !app.mesh) return;
  const all = app.result && app.result.candidates;
  const held = all && all[method];
  app.history.execute(new SetSettingCommand(app.model, 'method', method));
  if (held && held.report && held.report.verify && held.report.verify.sound) {
    held.candidates = all;
    try {
      await app.actions.showResult(held, performance.now());
    } finally {
      app.busy = null;
      app.actions.updateButtons();
    }
    return;
  }
  await app.actions.slice();
}

function fillCandidates(app, tbody, section) {
  tbody.replaceChildren();
  for (const r of candidateRows(section)) {
    const tr = document.createElement('tr');
    tr.dataset.testid = `auto-candidate-${r.method}`;
    tr.dataset.state = r.state;
    tr.className = r.state;
    for (const text of [r.method, r.verdict, r.supported, r.collisions, r.support, r.time, r.ms]) {
      const td = document.createElement('td');
      td.textContent = text;
      tr.append(td);
    }
    const picture = thumbnail(app.result && app.result.candidates && app.result.candidates[r.method], r.method);
    if (picture) tr.cells[0].append(document.createElement('br'), picture);
    // Any other candidate that made a program (or would have: stopped early) is one click away.
    const td = document.createElement('td');
    if (r.state !== 'chosen' && r.state !== 'failed') {
      const button = document.createElement('button');
      button.type = 'button';
      button.className = 'small';
      button.textContent = 'use';
      button.title = `slice again with method = ${r.method} (Ctrl+Z undoes the setting)`;
      button.dataset.testid = `auto-use-${r.method}`;
      button.disabled = !!app.busy;
      button.addEventListener('click', () => useMethod(app, r.method));
      td.append(button);
    }
    tr.append(td);
    tbody.append(tr);
  }
}

/** @type {import('./index.js').MethodModule} */
export const auto = {
  name: 'auto',
  data: {
    stageWeights: AUTO_STAGE_WEIGHTS,
    settingsGroup: 'Slicing',
    section: autoSection,
    summaryRows: autoSummaryRows,
    doneSummary: autoDoneSummary,
    machineHint: () => '',
  },
  panel: {
    show(app, section) {
      $('auto-report').hidden = !section;
      fillFigureList($('auto-figures'), autoSummaryRows(section), 'auto');
      fillCandidates(app, $('auto-candidates'), section);
    },
    wire() {},
    enable(app) {
      for (const b of $('auto-candidates').querySelectorAll('button')) b.disabled = !!app.busy;
    },
  },
  view: {
    setup() {},
  },
};
