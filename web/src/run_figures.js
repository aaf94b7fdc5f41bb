/*
 * run_figures.js — the "Run figures" panel: the open session's summary
 * figures (GET /v1/sessions/{id}/summary: top speed, peak track tension,
 * spectral peaks, shift times, IVS figures...), the same as `tanksim run`
 * writes to summary.json. Computed on request (Compute), since the daemon
 * reads every stored row for them; a run still going gives the figures of
 * the rows stored so far, and the note says so. A value whose unit a
 * display-unit toggle covers (a speed in mph, km/h or m/s, a rotation in
 * rad/s) is shown in the unit chosen there, converted as the charts are
 * (units.js), and shown again when the choice changes: the figures stayed in
 * the daemon's unit whatever the toggles said (review). The others (N, lbf,
 * Hz, s...) are shown in the unit the daemon names.
 */
import { api } from './api.js';
import { $, cell } from './dom.js';
import { hideError, showError } from './messages.js';
import { displayFrom, fmt, UNITS_CHANGED } from './units.js';

export function initRunFigures(state) {
  let asked = 0; /* the latest request: an older answer is dropped */
  let shown = null; /* {session, t, note, doc} of the figures on screen */

  /* no figures on screen */
  function blank() {
    shown = null;
    $('figures-table').replaceChildren();
    $('figures-note').textContent = '';
    $('figures-note').classList.remove('stale');
  }

  function clear() {
    asked++;
    blank();
    hideError($('figures-error'));
  }

  /* One row: name, value and unit, in the display unit when a toggle covers
   * the daemon's (the daemon's value and unit then in the tooltip). */
  function row(m) {
    const tr = document.createElement('tr');
    tr.dataset.name = m.name;
    const d = displayFrom(m.unit);
    const as = d && d.label !== m.unit && m.value !== null ? `${fmt(m.value, 5)} ${m.unit} as computed` : '';
    tr.title = [m.description, as].filter(Boolean).join(' · ');
    const value = m.value === null ? '—' : fmt(d ? m.value * d.factor : m.value, 5);
    tr.append(cell(m.name, 'mono'), cell(value, 'num'), cell(d ? d.label : m.unit === '1' ? '' : m.unit, 'muted'));
    return tr;
  }

  function render(doc) {
    const rows = (doc.metrics || []).map(row);
    $('figures-table').replaceChildren(...rows);
    const parts = [`${doc.rows} rows to t = ${fmt(doc.t)} s`, `${doc.dof} DOF`];
    if (!doc.complete) parts.push(`the session is ${doc.status}: figures of the rows stored so far`);
    if (!rows.length) parts.push('no figures for this scenario at this length');
    $('figures-note').textContent = parts.join(' · ');
    $('figures-note').classList.remove('stale');
    shown = { session: state.session, t: doc.t, note: parts.join(' · '), doc };
  }

  /* a display unit changed (units.js): the rows again, the note (out of date or not) as it is */
  window.addEventListener(UNITS_CHANGED, () => {
    if (shown) $('figures-table').replaceChildren(...(shown.doc.metrics || []).map(row));
  });

  /* The session moved on past the figures shown (a step or run since
   * Compute): say so, or a finished run kept its t = 0 figures (review).
   * The session by its id: the end of a run reads it again (a new object),
   * and rows streamed after that left the figures unmarked. */
  function update() {
    const s = state.session;
    if (!shown || !s || shown.session.id !== s.id) return;
    const n = state.store?.length || 0;
    const t = n ? state.store.t[n - 1] : s.t || 0;
    if (!(t > shown.t)) return;
    const e = $('figures-note');
    const text = `${shown.note} · out of date: the session is at t = ${fmt(t)} s now (Compute again)`;
    if (e.textContent !== text) e.textContent = text;
    e.classList.add('stale');
  }

  async function compute() {
    const s = state.session;
    if (!s) return;
    const mine = ++asked;
    hideError($('figures-error'));
    $('figures-btn').disabled = true;
    try {
      const doc = await api.summary(s.id);
      if (mine === asked && state.session === s) render(doc);
    } catch (e) {
      if (mine === asked) {
        blank();
        showError($('figures-error'), e);
      }
    } finally {
      $('figures-btn').disabled = !state.session;
    }
  }

  /* a session was opened, or none is: the figures shown were another's */
  function open() {
    clear();
    $('figures-btn').disabled = !state.session;
  }

  $('figures-btn').addEventListener('click', compute);
  return { open, clear: open, update };
}
