/*
 * schema_form.js — the "new session" form, generated from GET /v1/schema.
 *
 * The schema (JSON Schema 2020-12 built from the daemon's parameter table) has
 * one nested object per config section; each field carries type, x-unit,
 * minimum/maximum, enum and default. Every input here is made from that: enum
 * -> <select>, boolean -> checkbox, integer/number -> numeric input with the
 * unit and range beside it, number arrays -> comma-separated text, a string
 * with examples -> free text offering them (a <datalist>: /terrain/course's
 * shipped courses, typed blind before; a daemon with --client-files yes reads
 * other course names, so they are not an enum). The only
 * list kept in this file is WHICH fields are shown up front (the paper's key
 * knobs: track fidelity and mode counts, engine variant and fidelity, terrain,
 * speed controller target or rack, duration); all other fields sit under
 * "All parameters". Only fields the user edited are sent, as overrides on top
 * of the chosen preset, so the daemon's defaults <- preset <- overrides chain
 * stays the single source of values. Ranges and types are the daemon's to
 * check: its errors come back as problem+json errors[{pointer, message}] and
 * are shown on the field. Only what cannot be sent as a number at all (an
 * entry the browser cannot parse, "abc" in a number list, an emptied field)
 * is caught here, reported the same way, and nothing is sent.
 */
import { display, convertible, fmt } from './units.js';
import { parseNumeral, readNumber } from './number_input.js';

/* JSON Pointers of the fields shown up front, in this order (if the schema has them). */
const KEY_FIELDS = [
  '/run/duration',
  '/track/fidelity',
  '/track/n_long',
  '/track/n_trans',
  '/engine/variant',
  '/engine/fidelity',
  '/terrain/kind',
  '/terrain/course',
  '/control/mode',
  '/control/target_speed',
  '/control/rack',
  '/drive/kind',
  '/drive/torque',
];

const el = (tag, attrs = {}, ...kids) => {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (v === undefined || v === null || v === false) continue;
    if (k === 'class') e.className = v;
    else if (k === 'text') e.textContent = v;
    else e.setAttribute(k, v === true ? '' : v);
  }
  for (const k of kids) if (k) e.append(k);
  return e;
};

/** Flatten the schema into [{pointer, section, name, prop}] in schema order
 * (objects inside a section are walked too: name "a/b" for /section/a/b). */
export function schemaFields(schema) {
  const out = [];
  const walk = (section, sectionDoc, prefix, props) => {
    for (const [name, prop] of Object.entries(props)) {
      const rel = prefix ? `${prefix}/${name}` : name;
      if (prop.type === 'object' && prop.properties) walk(section, sectionDoc, rel, prop.properties);
      else out.push({ pointer: `/${section}/${rel}`, section, name: rel, prop, sectionDoc });
    }
  };
  for (const [section, sec] of Object.entries(schema.properties || {})) {
    if (sec.type !== 'object' || !sec.properties) continue;
    walk(section, sec.description || '', '', sec.properties);
  }
  return out;
}

/** The range {min, max} of the config field at pointer in the schema (undefined ends when unknown). */
export function fieldRange(schema, pointer) {
  const f = schema ? schemaFields(schema).find((x) => x.pointer === pointer) : null;
  return { min: f?.prop.minimum, max: f?.prop.maximum };
}

function getPath(doc, pointer) {
  let v = doc;
  for (const part of pointer.split('/').slice(1)) {
    if (v === null || typeof v !== 'object') return undefined;
    v = v[part];
  }
  return v;
}

function setPath(doc, pointer, value) {
  const parts = pointer.split('/').slice(1);
  let o = doc;
  for (const p of parts.slice(0, -1)) o = o[p] = o[p] || {};
  o[parts[parts.length - 1]] = value;
}

/* A number's bounds: its own minimum/maximum, or those of an "off value or a
 * range" field (`anyOf: [{const: 0}, {minimum, maximum}]`, e.g. /run/max_step,
 * /driveline/engine_macro_step), whose off value is returned as `off`. */
function bounds(prop) {
  if (!Array.isArray(prop.anyOf)) return { lo: prop.minimum, hi: prop.maximum };
  const off = prop.anyOf.find((a) => 'const' in a);
  const range = prop.anyOf.find((a) => 'minimum' in a || 'maximum' in a) || {};
  return { lo: range.minimum, hi: range.maximum, off: off ? off.const : undefined };
}

/* The input's min attribute: the range's low end, or the off value below it. */
function lowest(prop) {
  const { lo, off } = bounds(prop);
  if (lo === undefined || off === undefined) return lo ?? off;
  return Math.min(lo, off);
}

function rangeText(prop) {
  const { lo, hi, off } = bounds(prop);
  const or = off !== undefined ? `${fmt(off)} or ` : '';
  if (lo === undefined && hi === undefined) return off !== undefined ? fmt(off) : '';
  if (lo !== undefined && hi !== undefined) return `${or}${fmt(lo)} … ${fmt(hi)}`;
  return or + (lo !== undefined ? `≥ ${fmt(lo)}` : `≤ ${fmt(hi)}`);
}

function labelText(f) {
  return f.name.replace(/_/g, ' ').replace(/\//g, ' › ');
}

export class SchemaForm {
  /**
   * root: container element; schema: GET /v1/schema document.
   * The form owns its inputs; call setBase(doc) with the preset's values.
   */
  constructor(root, schema) {
    this.root = root;
    this.fields = schemaFields(schema);
    this.inputs = new Map(); /* pointer -> {f, input, row, msg, hint} */
    this.dirty = new Set();
    this.build();
  }

  /* Redo every "= 25 mph" hint (the display unit was changed elsewhere: the unit toggles). */
  updateHints() {
    for (const pointer of this.inputs.keys()) this.updateHint(pointer);
  }

  build() {
    const byPtr = new Map(this.fields.map((f) => [f.pointer, f]));
    const key = el('div', { class: 'form-grid key-fields' });
    for (const p of KEY_FIELDS) if (byPtr.has(p)) key.append(this.row(byPtr.get(p), true));
    this.more = el('details', { class: 'all-params' }, el('summary', { text: 'All parameters' }));
    let section = null;
    let grid = null;
    for (const f of this.fields) {
      if (KEY_FIELDS.includes(f.pointer)) continue;
      if (f.section !== section) {
        section = f.section;
        this.more.append(el('h4', { text: section, title: f.sectionDoc }));
        grid = el('div', { class: 'form-grid' });
        this.more.append(grid);
      }
      grid.append(this.row(f, false));
    }
    this.root.replaceChildren(key, this.more);
  }

  row(f, isKey) {
    const { prop } = f;
    const id = `fld-${f.section}-${f.name.replace(/\//g, '-')}`;
    let input;
    if (Array.isArray(prop.enum)) {
      input = el('select', { id });
      for (const v of prop.enum) input.append(el('option', { value: v, text: v }));
    } else if (prop.type === 'boolean') {
      input = el('input', { id, type: 'checkbox' });
    } else if (prop.type === 'integer' || prop.type === 'number') {
      input = el('input', {
        id,
        type: 'number',
        step: prop.type === 'integer' ? '1' : 'any',
        min: lowest(prop),
        max: bounds(prop).hi,
        inputmode: 'decimal',
      });
    } else if (prop.type === 'array') {
      input = el('input', { id, type: 'text', placeholder: 'comma-separated numbers' });
    } else if (Array.isArray(prop.examples) && prop.examples.length) {
      input = el('input', { id, type: 'text', list: `${id}-list`, autocomplete: 'off' });
    } else {
      input = el('input', { id, type: 'text' });
    }
    input.dataset.pointer = f.pointer;
    const offered = input.hasAttribute('list') ? el('datalist', { id: `${id}-list` }, ...prop.examples.map((v) => el('option', { value: v }))) : null;
    const unit = prop['x-unit'] && prop['x-unit'] !== '1' ? prop['x-unit'] : '';
    const hint = el('span', { class: 'hint' });
    const msg = el('div', { class: 'field-error', role: 'alert' });
    const label = el(
      'label',
      { for: id, title: `${f.pointer}${prop.description ? ' — ' + prop.description : ''}` },
      el('span', { class: 'label-name', text: isKey ? `${f.section} ${labelText(f)}` : labelText(f) }),
      unit ? el('span', { class: 'unit', text: `[${unit}]` }) : null,
    );
    const range = rangeText(prop);
    const row = el(
      'div',
      { class: 'field', 'data-pointer': f.pointer, title: isKey ? undefined : prop.description },
      label,
      el('div', { class: 'control' }, input, offered, hint),
      el(
        'div',
        { class: 'desc' },
        prop.description ? el('span', { class: 'd-text', text: prop.description }) : null,
        prop.description && range ? el('span', { class: 'd-text', text: ' · ' }) : null,
        range ? el('span', { class: 'd-range', text: `range ${range}` }) : null,
        offered ? el('span', { class: 'd-range', text: `${prop.description ? ' · ' : ''}e.g. ${prop.examples.join(', ')}` }) : null,
      ),
      msg,
    );
    const onChange = () => {
      this.dirty.add(f.pointer);
      row.classList.add('edited');
      this.clearError(f.pointer);
      this.updateHint(f.pointer);
    };
    input.addEventListener('input', onChange);
    input.addEventListener('change', onChange);
    this.inputs.set(f.pointer, { f, input, row, msg, hint, unit });
    return row;
  }

  updateHint(pointer) {
    const e = this.inputs.get(pointer);
    if (!e || !convertible(e.unit)) return;
    const v = parseNumeral(e.input.value);
    const d = display(e.unit);
    e.hint.textContent = Number.isFinite(v) && d.factor !== 1 ? `= ${fmt(v * d.factor)} ${d.label}` : '';
  }

  /** Show the effective values of a preset (resolved over the schema defaults). */
  setBase(presetDoc) {
    this.dirty.clear();
    for (const [pointer, e] of this.inputs) {
      let v = getPath(presetDoc || {}, pointer);
      if (v === undefined) v = e.f.prop.default;
      this.writeInput(e, v);
      e.row.classList.remove('edited');
      this.clearError(pointer);
      this.updateHint(pointer);
    }
  }

  writeInput(e, v) {
    const { input, f } = e;
    if (f.prop.type === 'boolean') input.checked = !!v;
    else if (Array.isArray(v)) input.value = v.join(', ');
    else input.value = v === undefined || v === null ? '' : String(v);
  }

  /** The value of an edited field: {value} or {error} (a message naming the field). */
  readInput(e) {
    const { input, f } = e;
    const t = f.prop.type;
    if (t === 'boolean') return { value: input.checked };
    if (t === 'integer' || t === 'number') return readNumber(input, { name: f.pointer });
    if (t === 'array') {
      const items = input.value.split(/[\s,;]+/).filter(Boolean);
      if (!['number', 'integer'].includes(f.prop.items?.type)) return { value: items };
      const nums = items.map(parseNumeral);
      const bad = nums.findIndex((v) => !Number.isFinite(v));
      return bad < 0 ? { value: nums } : { error: `${f.pointer}: numbers separated by commas expected, got '${items[bad]}'` };
    }
    return { value: input.value };
  }

  /** The overrides document of the fields the user edited: {doc, errors[{pointer, message}]}. */
  overrides() {
    const doc = {};
    const errors = [];
    for (const p of this.dirty) {
      const r = this.readInput(this.inputs.get(p));
      if (r.error) errors.push({ pointer: p, message: r.error });
      else setPath(doc, p, r.value);
    }
    return { doc, errors };
  }

  clearError(pointer) {
    const e = this.inputs.get(pointer);
    if (!e) return;
    e.row.classList.remove('invalid');
    e.msg.textContent = '';
  }

  clearErrors() {
    for (const p of this.inputs.keys()) this.clearError(p);
  }

  /**
   * Mark the fields named by problem errors[].pointer (the caller shows the
   * whole list, those that match no field too, in the general message box).
   */
  showErrors(errors) {
    let first = null;
    for (const err of errors || []) {
      const e = this.inputs.get(err.pointer) || this.inputs.get(parentField(err.pointer, this.inputs));
      if (!e) continue;
      e.row.classList.add('invalid');
      e.msg.textContent = e.msg.textContent ? `${e.msg.textContent}; ${err.message}` : err.message;
      if (!first) first = e;
    }
    if (first) {
      if (this.more.contains(first.row)) this.more.open = true;
      first.input.focus({ preventScroll: true });
      first.row.scrollIntoView({ block: 'center', behavior: 'smooth' });
    }
  }
}

/* "/drive/table_t/3" -> "/drive/table_t" when that is a field. */
function parentField(pointer, inputs) {
  if (!pointer) return undefined;
  let p = pointer;
  while (p.lastIndexOf('/') > 0) {
    p = p.slice(0, p.lastIndexOf('/'));
    if (inputs.has(p)) return p;
  }
  return undefined;
}
