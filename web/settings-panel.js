// SPDX-License-Identifier: MIT
// Settings panel: a schema of fields, a settings model that signals changes, and every user edit
// as a small command (execute/undo/serialize) kept in a history. The panel redraws its inputs from
// the model's 'change' signal, so undo and programmatic edits show up the same way.

/** Direction presets (part-frame unit vectors, 'x,y,z'). Tilts lean +Z towards -Y or +X. */
export const DIRECTION_PRESETS = [
  { label: '+Z (planar)', value: '0,0,1' },
  { label: 'tilt 15° about X', value: dir(15, 'x') },
  { label: 'tilt 30° about X', value: dir(30, 'x') },
  { label: 'tilt 45° about X', value: dir(45, 'x') },
  { label: 'tilt 30° about Y', value: dir(30, 'y') },
  { label: 'tilt 45° about Y', value: dir(45, 'y') },
];

function dir(deg, axis) {
  const r = (deg * Math.PI) / 180;
  const s = Math.sin(r);
  const c = Math.cos(r);
  return parseDirection(axis === 'x' ? `0,${-s},${c}` : `${s},0,${c}`);
}

function round4(x) {
  return Math.round(x * 1e4) / 1e4;
}

/**
 * Field schema: key (the facade's setting key), label, type, default and bounds. Units in labels.
 * Groups render as sub-headings.
 */
export const SETTINGS_SCHEMA = [
  { group: 'Slicing', key: 'layer_height', label: 'layer height (mm)', type: 'number', value: 0.2, min: 0.02, max: 2, step: 0.01 },
  { group: 'Slicing', key: 'nozzle', label: 'nozzle (mm)', type: 'number', value: 0.4, min: 0.1, max: 2, step: 0.05 },
  { group: 'Slicing', key: 'line_width', label: 'line width (mm, 0 = auto)', type: 'number', value: 0, min: 0, max: 3, step: 0.01 },
  { group: 'Slicing', key: 'walls', label: 'walls', type: 'integer', value: 2, min: 0, max: 20, step: 1 },
  { group: 'Slicing', key: 'top_layers', label: 'top layers', type: 'integer', value: 4, min: 0, max: 50, step: 1 },
  { group: 'Slicing', key: 'bottom_layers', label: 'bottom layers', type: 'integer', value: 4, min: 0, max: 50, step: 1 },
  { group: 'Slicing', key: 'infill', label: 'infill (%)', type: 'number', value: 20, min: 0, max: 100, step: 1 },
  { group: 'Slicing', key: 'infill_pattern', label: 'infill pattern', type: 'select', value: 'grid',
    options: [{ label: 'grid', value: 'grid' }, { label: 'lines', value: 'lines' }] },
  { group: 'Slicing', key: 'direction', label: 'slicing direction', type: 'direction', value: '0,0,1' },
  { group: 'Speed', key: 'print_speed', label: 'print speed (mm/s)', type: 'number', value: 50, min: 1, max: 1000, step: 1 },
  { group: 'Speed', key: 'travel_speed', label: 'travel speed (mm/s)', type: 'number', value: 150, min: 1, max: 2000, step: 1 },
  { group: 'Speed', key: 'retract_length', label: 'retract (mm)', type: 'number', value: 0.8, min: 0, max: 20, step: 0.1 },
  { group: 'Placement', key: 'fit_mm', label: 'fit largest side (mm, 0 = off)', type: 'number', value: 0, min: 0, max: 1000, step: 1 },
  { group: 'Placement', key: 'scale', label: 'scale', type: 'number', value: 1, min: 0.0001, max: 10000, step: 0.1 },
  { group: 'Placement', key: 'up', label: 'up axis of the file', type: 'select', value: 'z',
    options: ['z', '-z', 'y', '-y', 'x', '-x'].map((v) => ({ label: v.startsWith('-') ? `−${v.slice(1).toUpperCase()}` : `+${v.toUpperCase()}`, value: v })) },
  { group: 'Placement', key: 'rotate_x_deg', label: 'rotate X (°)', type: 'number', value: 0, min: -360, max: 360, step: 15 },
  { group: 'Placement', key: 'rotate_y_deg', label: 'rotate Y (°)', type: 'number', value: 0, min: -360, max: 360, step: 15 },
  { group: 'Placement', key: 'rotate_z_deg', label: 'rotate Z (°)', type: 'number', value: 0, min: -360, max: 360, step: 15 },
  { group: 'Placement', key: 'center', label: 'centre on the plate', type: 'checkbox', value: true },
];

/** Keys that change the placement (the model must be placed again). */
export const PLACEMENT_KEYS = ['scale', 'fit_mm', 'up', 'rotate_x_deg', 'rotate_y_deg', 'rotate_z_deg', 'center'];

/**
 * Parse a direction 'x,y,z' into a normalised string, or null when it is not three finite numbers
 * with a non-zero length.
 */
export function parseDirection(text) {
  const parts = String(text).split(/[\s,;]+/).filter(Boolean).map(Number);
  if (parts.length !== 3 || !parts.every(Number.isFinite)) return null;
  const len = Math.hypot(...parts);
  if (!(len > 1e-9)) return null;
  return parts.map((x) => round4(x / len)).join(',');
}

/** Check a value against its schema field; returns the normalised value or throws a RangeError. */
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
    case 'direction': {
      const d = parseDirection(value);
      if (!d) throw new RangeError(`${field.label}: give three numbers x,y,z (not all zero)`);
      return d;
    }
    default:
      throw new RangeError(`unknown field type ${field.type}`);
  }
}

/** Current settings; dispatches 'change' events with detail {key, value}. */
export class SettingsModel extends EventTarget {
  constructor(schema = SETTINGS_SCHEMA) {
    super();
    this.schema = schema;
    this.values = Object.fromEntries(schema.map((f) => [f.key, f.value]));
  }

  field(key) {
    const f = this.schema.find((x) => x.key === key);
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

  /** Settings object for slicer.slice(): every key of the schema. */
  toSettings() {
    return { ...this.values };
  }

  /** Placement object for slicer.loadMesh(). */
  toPlacement() {
    return Object.fromEntries(PLACEMENT_KEYS.map((k) => [k, this.values[k]]));
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
 * Render the panel into `host`. Inputs carry data-testid="setting-<key>" (the direction's free text
 * is "setting-direction-custom"). Edits go through history.execute(new SetSettingCommand(...)).
 * @returns {{refresh: () => void}}
 */
export function createSettingsPanel(host, model, history) {
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
  let group = null;
  for (const field of model.schema) {
    if (field.group !== group) {
      group = field.group;
      const h = document.createElement('h3');
      h.textContent = group;
      host.append(h);
    }
    const row = document.createElement('label');
    row.className = 'field';
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
      sel.dataset.testid = `setting-${field.key}`;
      for (const o of field.options) sel.append(new Option(o.label, o.value));
      sel.addEventListener('change', () => edit(sel.value, sel));
      row.append(sel);
      inputs.set(field.key, { refresh: (v) => { sel.value = v; } });
    } else if (field.type === 'checkbox') {
      const box = document.createElement('input');
      box.type = 'checkbox';
      box.dataset.testid = `setting-${field.key}`;
      box.addEventListener('change', () => edit(box.checked, box));
      row.classList.add('check');
      row.append(box);
      inputs.set(field.key, { refresh: (v) => { box.checked = v; } });
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
      num.dataset.testid = `setting-${field.key}`;
      num.min = field.min;
      num.max = field.max;
      num.step = field.step;
      num.addEventListener('change', () => edit(num.value, num));
      row.append(num);
      inputs.set(field.key, { refresh: (v) => { num.value = String(v); } });
    }
    host.append(row);
  }
  host.append(problem);

  const refresh = () => {
    for (const [key, input] of inputs) input.refresh(model.get(key));
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
