/*
 * create_form.js — the "new session" form: the preset list (GET
 * /v1/presets), the fields generated from GET /v1/schema (SchemaForm) and
 * Create, which sends only the fields changed from the preset and opens the
 * new session. A rejected field is marked by its errors[].pointer.
 */
import { api, ApiError } from './api.js';
import { $, presetOptions } from './dom.js';
import { hideError, showError } from './messages.js';
import { SchemaForm } from './schema_form.js';
import { UNITS_CHANGED } from './units.js';

export function initCreateForm({ refreshList, open }) {
  let form = null; /* the SchemaForm, once the schema loaded */

  /* the "= 25 mph" hints follow the unit toggles (one listener: load() replaces the form) */
  window.addEventListener(UNITS_CHANGED, () => form?.updateHints());

  /* Fetch the schema and build the form with the preset list (GET /v1/presets);
     the schema, or throws what the daemon said. */
  async function load(list) {
    const schema = await api.schema();
    form = new SchemaForm($('schema-form'), schema);
    const sel = $('preset-select');
    /* a preset that serves other commands only (the eigenanalysis ones: POST /v1/modes)
       stays visible but cannot start a session */
    presetOptions(sel, list, (p) => (Array.isArray(p.commands) && !p.commands.includes('session') ? `${p.commands.join(', ')} only` : ''));
    sel.onchange = () => loadPreset(list);
    $('reset-form').onclick = () => loadPreset(list);
    await loadPreset(list);
    return schema;
  }

  /* Put the chosen preset's values in the form. Only the latest call's answer
     is used: a slower answer to an earlier choice (or Reset) is dropped. */
  let presetSeq = 0;
  async function loadPreset(list) {
    const seq = ++presetSeq;
    const name = $('preset-select').value;
    const meta = list.find((p) => p.name === name);
    $('preset-desc').textContent = [meta?.kind && `scenario ${meta.kind}.`, meta?.description].filter(Boolean).join(' ');
    hideError($('create-error'));
    let doc = {};
    let error = null;
    if (name) {
      try {
        doc = (await api.preset(name)).config; /* the resolved document (GET /v1/presets/{name}) */
      } catch (e) {
        error = e;
      }
    }
    if (seq !== presetSeq) return;
    if (error) showError($('create-error'), error);
    form.setBase(doc);
  }

  async function onCreate(ev) {
    ev.preventDefault();
    const box = $('create-error');
    hideError(box);
    if (!form) {
      showError(box, new ApiError(0, { title: 'No form', detail: 'the run-config schema could not be loaded (see above); reload the page' }));
      return;
    }
    form.clearErrors();
    $('create-btn').disabled = true;
    try {
      const { doc: overrides, errors } = form.overrides();
      if (errors.length) throw new ApiError(0, { title: 'Not sent: fix the marked fields', errors });
      const s = await api.createSession({ preset: $('preset-select').value || undefined, ...overrides });
      await refreshList();
      await open(s.id, s);
    } catch (e) {
      if (e instanceof ApiError) form.showErrors(e.errors);
      showError(box, e);
    } finally {
      $('create-btn').disabled = false;
    }
  }

  $('create-form').addEventListener('submit', onCreate);

  return { load };
}
