// SPDX-License-Identifier: MIT
// Settings panel: a settings model over the settings fields (settings-fields.js settingsFields:
// the page's rows over the core's settings table) that signals changes, and every user edit as a small command (execute/undo/serialize) kept in a history. The panel
// redraws its inputs from the model's 'change' signal, so undo and programmatic edits show up the
// same way.
import { isPlacementKey, placementOf } from './placement.js';
import { DIRECTION_PRESETS, parseDirection } from './settings-fields.js';

/** Check a value against its settings field; returns the normalised value or throws a RangeError. */
export function normaliseValue(field, value) {
  switch (field.type) {
    case 'number':
    case 'integer': {
      const x = typeof value === 'number' ? value : Number(String(value).trim());
      if (String(value).trim() === '' || !Number.isFinite(x)) throw new RangeError(`${field.label}: not a number`);
      if (field.type === 'integer' && !Number.isInteger(x)) throw new RangeError(`${field.label}: must be a whole number`);
      if (x < field.min || x > field.max) throw new RangeError(`${field.label}: must be within ${field.min}..${field.max}`);
      return x;
    }
    case 'select':
      if (!field.options.some((o) => o.value === value)) throw new RangeError(`${field.label}: unknown choice ${value}`);
      return value;
    case 'checkbox':
      return !!value;
    case 'text': {
      // One line of text (it travels as one `key=value` setting line); the core checks it.
      const text = value === null || value === undefined ? '' : String(value).trim();
      if (/[\n\r]/.test(text)) throw new RangeError(`${field.label}: one line of text`);
      return text;
    }
    case 'json': {
      // '' (none) or one line of JSON object text (it travels as one `key=value` setting line).
      if (value === '' || value === null || value === undefined) return '';
      const text = String(value);
      let parsed;
      try {
        parsed = JSON.parse(text);
      } catch (err) {
        throw new RangeError(`${field.label}: not JSON (${err.message})`);
      }
      if (!parsed || typeof parsed !== 'object' || Array.isArray(parsed)) throw new RangeError(`${field.label}: not a JSON object`);
      return /[\n\r]/.test(text) ? JSON.stringify(parsed) : text;
    }
    case 'direction': {
      const d = parseDirection(value);
      if (!d) throw new RangeError(`${field.label}: give three numbers x,y,z (not all zero)`);
      return d;
    }
    default:
      throw new RangeError(`unknown field type ${field.type}`);
  }
}

/**
 * Current settings over `fields` (settingsFields(coreSchema)), starting at their defaults;
 * dispatches 'change' events with detail {key, value}.
 */
export class SettingsModel extends EventTarget {
  constructor(fields) {
    super();
    if (!Array.isArray(fields)) throw new TypeError('SettingsModel: give the settings fields (settingsFields(coreSchema))');
    this.fields = fields;
    this.values = Object.fromEntries(fields.map((f) => [f.key, f.value]));
  }

  field(key) {
    const f = this.fields.find((x) => x.key === key);
    if (!f) throw new RangeError(`unknown setting ${key}`);
    return f;
  }

  get(key) {
    return this.values[key];
  }

  /** Set a value (validated); signals 'change' when it differs. */
  set(key, value) {
    const v = normaliseValue(this.field(key), value);
    if (this.values[key] === v) return;
    this.values[key] = v;
    this.dispatchEvent(new CustomEvent('change', { detail: { key, value: v } }));
  }

  /** Settings object for slicer.slice(): every field's key (machine_json only when set). */
  toSettings() {
    const out = { ...this.values };
    if (!out.machine_json) delete out.machine_json;
    return out;
  }

  /**
   * Settings object for slicer.slice(): the placement keys (they override the placement the mesh
   * was loaded with) and the other values that differ from the fields' defaults (the core's), so
   * the request names what the user chose and the core's defaults apply to the rest. Fields whose
   * sendIf is false are left out.
   */
  toSliceSettings() {
    return Object.fromEntries(this.fields
      .filter((f) => isPlacementKey(f.key)
        || (this.values[f.key] !== f.value && !(f.type === 'json' && !this.values[f.key])
          && (!f.sendIf || f.sendIf(this.values))))
      .map((f) => [f.key, this.values[f.key]]));
  }

  /** Placement object for slicer.loadMesh(). */
  toPlacement() {
    return placementOf(this.values);
  }
}

/** One edit: set `key` to `value`, remembering the previous value. */
export class SetSettingCommand {
  constructor(model, key, value) {
    this.model = model;
    this.key = key;
    this.value = normaliseValue(model.field(key), value);
    this.previous = model.get(key);
  }

  execute() {
    this.model.set(this.key, this.value);
  }

  undo() {
    this.model.set(this.key, this.previous);
  }

  serialize() {
    return { type: 'SetSetting', key: this.key, value: this.value, previous: this.previous };
  }
}

/** Undo/redo stacks of commands. */
export class History extends EventTarget {
  constructor() {
    super();
    this.done = [];
    this.undone = [];
  }

  execute(command) {
    command.execute();
    this.done.push(command);
    this.undone.length = 0;
    this.dispatchEvent(new Event('change'));
  }

  undo() {
    const c = this.done.pop();
    if (!c) return false;
    c.undo();
    this.undone.push(c);
    this.dispatchEvent(new Event('change'));
    return true;
  }

  redo() {
    const c = this.undone.pop();
    if (!c) return false;
    c.execute();
    this.done.push(c);
    this.dispatchEvent(new Event('change'));
    return true;
  }

  serialize() {
    return this.done.map((c) => c.serialize());
  }
}

/**
 * Render the panel into `host`. Inputs carry data-testid="setting-<key>" (or the field's testid; the
 * direction's free text is "setting-direction-custom"). Edits go through
 * history.execute(new SetSettingCommand(...)). groupHosts: {group name: element} renders that
 * group's rows into another element (without a sub-heading).
 * @returns {{refresh: () => void}}
 */
export function createSettingsPanel(host, model, history, { groupHosts = {} } = {}) {
  host.replaceChildren();
  const title = document.createElement('h2');
  title.textContent = 'Settings';
  const undoBtn = button('undo', 'settings-undo', () => history.undo());
  const redoBtn = button('redo', 'settings-redo', () => history.redo());
  const head = document.createElement('div');
  head.className = 'settings-head';
  head.append(title, undoBtn, redoBtn);
  host.append(head);

  const problem = document.createElement('p');
  problem.className = 'field-problem';
  problem.dataset.testid = 'settings-problem';
  problem.hidden = true;

  const inputs = new Map();
  const rows = [];
  const headings = [];  // [h3, group]: hidden when every row of the group is hidden
  let group = null;
  for (const field of model.fields) {
    if (field.hidden) continue;
    const target = groupHosts[field.group] || host;
    if (field.group !== group) {
      group = field.group;
      if (target === host) {
        const h = document.createElement('h3');
        h.textContent = group;
        host.append(h);
        headings.push([h, group]);
      }
    }
    const testid = field.testid || `setting-${field.key}`;
    const row = document.createElement('label');
    row.className = 'field';
    // The core's help text (settings_table.cpp) as the row's tooltip.
    if (field.help) row.title = field.help;
    const name = document.createElement('span');
    name.textContent = field.label;
    row.append(name);
    const edit = (value, el) => {
      try {
        const command = new SetSettingCommand(model, field.key, value);
        if (command.value !== command.previous) history.execute(command);
        el.classList.remove('invalid');
        problem.hidden = true;
      } catch (err) {
        el.classList.add('invalid');
        problem.textContent = err.message;
        problem.hidden = false;
      }
    };
    if (field.type === 'select') {
      const sel = document.createElement('select');
      sel.dataset.testid = testid;
      for (const o of field.options) sel.append(new Option(o.label, o.value));
      sel.addEventListener('change', () => edit(sel.value, sel));
      row.append(sel);
      inputs.set(field.key, { refresh: (v) => { sel.value = v; } });
    } else if (field.type === 'checkbox') {
      const box = document.createElement('input');
      box.type = 'checkbox';
      box.dataset.testid = testid;
      box.addEventListener('change', () => edit(box.checked, box));
      row.classList.add('check');
      row.append(box);
      inputs.set(field.key, { refresh: (v) => { box.checked = v; } });
    } else if (field.type === 'text') {
      const text = document.createElement('input');
      text.type = 'text';
      text.dataset.testid = testid;
      text.spellcheck = false;
      if (field.placeholder) text.placeholder = field.placeholder;
      text.addEventListener('change', () => edit(text.value, text));
      row.append(text);
      inputs.set(field.key, { refresh: (v) => { text.value = v; } });
    } else if (field.type === 'direction') {
      const sel = document.createElement('select');
      sel.dataset.testid = `setting-${field.key}`;
      for (const p of DIRECTION_PRESETS) sel.append(new Option(p.label, p.value));
      sel.append(new Option('custom…', 'custom'));
      const text = document.createElement('input');
      text.type = 'text';
      text.dataset.testid = `setting-${field.key}-custom`;
      text.placeholder = 'x,y,z';
      text.spellcheck = false;
      sel.addEventListener('change', () => {
        if (sel.value === 'custom') {
          text.hidden = false;
          text.focus();
        } else {
          edit(sel.value, sel);
        }
      });
      text.addEventListener('change', () => edit(text.value, text));
      row.classList.add('wide');
      row.append(sel, text);
      inputs.set(field.key, {
        refresh: (v) => {
          const preset = DIRECTION_PRESETS.find((p) => p.value === v);
          sel.value = preset ? preset.value : 'custom';
          text.value = v;
          text.hidden = !!preset;
        },
      });
    } else {
      const num = document.createElement('input');
      num.type = 'number';
      num.dataset.testid = testid;
      num.min = field.min;
      num.max = field.max;
      num.step = field.step;
      num.addEventListener('change', () => edit(num.value, num));
      row.append(num);
      inputs.set(field.key, { refresh: (v) => { num.value = String(v); } });
    }
    row.dataset.group = field.group;
    if (field.showIf) rows.push([row, field.showIf]);
    target.append(row);
  }
  host.append(problem);

  const refresh = () => {
    for (const [key, input] of inputs) input.refresh(model.get(key));
    for (const [row, showIf] of rows) row.hidden = !showIf(model.values);
    for (const [h, name] of headings) {
      h.hidden = ![...host.querySelectorAll('label.field')].some((r) => r.dataset.group === name && !r.hidden);
    }
    undoBtn.disabled = history.done.length === 0;
    redoBtn.disabled = history.undone.length === 0;
  };
  model.addEventListener('change', refresh);
  history.addEventListener('change', refresh);
  refresh();
  return { refresh };
}

function button(text, testid, onClick) {
  const b = document.createElement('button');
  b.type = 'button';
  b.textContent = text;
  b.dataset.testid = testid;
  b.className = 'small';
  b.addEventListener('click', onClick);
  return b;
}
