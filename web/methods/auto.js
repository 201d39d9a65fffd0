// SPDX-License-Identifier: MIT
// method = auto in the registry (index.js): not a method of its own but the choice among them.
// The result is the chosen method's (its sections and views show as usual); the group
// 'auto-report' adds the candidates side by side (auto-data.js): verdict, supported, collisions,
// support, time, how long each took, the chosen one marked.
import { byTestId as $, fillFigureList } from '../panel-dom.js';
import { AUTO_STAGE_WEIGHTS, autoDoneSummary, autoSection, autoSummaryRows, candidateRows } from './auto-data.js';

function fillCandidates(tbody, section) {
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
      fillCandidates($('auto-candidates'), section);
    },
    wire() {},
  },
  view: {
    setup() {},
  },
};
