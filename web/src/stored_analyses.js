/*
 * stored_analyses.js — the Analyses panel's list of stored analyses (GET
 * /v1/analyses, newest first): when each was started, its kind, what was
 * asked (the list's summary of the request the daemon stored — preset,
 * engine fidelity, schedule; not the body) and its status. Show fetches the operation (GET
 * /v1/operations/{id}) and hands it to the form of its kind
 * (analysis_op.js showStored: the response drawn where the form draws its
 * own, or the error in its error box, and the outcome on its progress bar;
 * the form's inputs set to what the analysis asked);
 * Delete removes a finished one (DELETE /v1/analyses/{id}). The
 * list is drawn again on page load, when a form's analysis starts or ends
 * (refresh / changed) and after a delete, and every POLL_MS while a listed
 * analysis runs (one another client started, say) and the page is not hidden.
 * On page load the forms follow the analyses still running (analysis_op.js
 * attach: progress, Cancel, result), and deleting the analysis a form shows
 * (its shown()) takes its result and its progress off screen (its reset()).
 */
import { api } from './api.js';
import { $, cell, pill } from './dom.js';
import { hideError, showError } from './messages.js';
import { outcomeOf } from './operation.js';

const KIND_LABEL = { engine_map: 'engine map', tune: 'tuning' };
const POLL_MS = 2000; /* [ms] list refresh while an analysis in it runs */

/* What was asked, from the list's summary of the stored request (asked: its
   body's preset and engine_fidelity, and the query's schedule_*; the list
   carries no bodies): "preset · fidelity engine · schedule over mass 50000,60000". */
function asked(a) {
  const parts = [a?.preset || 'config without preset'];
  if (a?.engine_fidelity) parts.push(`${a.engine_fidelity} engine`);
  for (const [k, v] of Object.entries(a || {})) if (k.startsWith('schedule_')) parts.push(`schedule over ${k.slice(9)} ${String(v).replaceAll(',', ', ')}`);
  return parts.join(' · ');
}

function button(label, title, onClick) {
  const b = document.createElement('button');
  b.type = 'button';
  b.className = 'small ghost';
  b.textContent = label;
  b.setAttribute('aria-label', title);
  b.addEventListener('click', onClick);
  return b;
}

/* form(kind): the analysis form of that kind ({showStored, attach, reset, shown},
   analysis_op.js; made after this list), undefined for a kind the page has no form for. */
export function initStoredAnalyses({ form: formOf }) {
  const box = $('stored-error');
  const tbody = $('stored-table').querySelector('tbody');
  let drawn = 0; /* the latest refresh: an earlier one answering late is dropped */
  let showing = 0; /* the same for Show */
  let listFailed = false; /* the error box holds why the list could not be loaded */
  let running = false; /* the list drawn last has a running analysis */
  let poll = 0; /* the timer of the next refresh while one runs */

  function clearBox() {
    hideError(box);
    listFailed = false;
  }

  /* error_code: the google.rpc code of its error (0: none) */
  const outcome = (a) => (a.done ? outcomeOf(a.error_code ? { code: a.error_code } : null) : 'running');

  /* Refresh again in POLL_MS while the list drawn last has a running analysis (a hidden page only waits). */
  function schedule() {
    clearTimeout(poll);
    poll = running ? setTimeout(() => (document.hidden ? schedule() : refresh()), POLL_MS) : 0;
  }

  /* attach: the forms follow the analyses still running (the page was loaded while they ran). */
  async function refresh({ attach = false } = {}) {
    const me = ++drawn;
    let list;
    try {
      list = (await api.analyses()).analyses || [];
    } catch (e) {
      if (me !== drawn) return;
      showError(box, e);
      listFailed = true;
      schedule(); /* still polling while the last list had one running */
      return;
    }
    if (me !== drawn) return;
    if (listFailed) hideError(box); /* an error of Show or Delete stays */
    listFailed = false;
    tbody.replaceChildren(...list.map((a) => row(a, outcome(a))));
    $('stored-empty').hidden = list.length > 0;
    running = list.some((a) => !a.done);
    /* a form follows one analysis: of several running (long jobs run
       max(1, threads - 1) at once), the newest, the first in the list */
    if (attach) for (const a of list) if (!a.done) formOf(a.kind)?.attach(a.id);
    schedule();
  }

  function row(a, status) {
    const tr = document.createElement('tr');
    tr.dataset.id = a.id;
    tr.dataset.kind = a.kind;
    const created = new Date(a.created * 1000);
    const time = document.createElement('time');
    time.dateTime = created.toISOString();
    time.textContent = created.toLocaleString(undefined, { dateStyle: 'short', timeStyle: 'medium' });
    const what = cell(asked(a.asked), 'asked');
    what.title = JSON.stringify(a.asked);
    const kind = KIND_LABEL[a.kind] || a.kind;
    const show = button('Show', `show the ${kind} of ${time.textContent}`, () => onShow(a));
    show.disabled = !a.done || !formOf(a.kind);
    const del = button('Delete', `delete the ${kind} of ${time.textContent}`, () => onDelete(a, `${kind} of ${time.textContent}`));
    del.classList.add('danger');
    del.disabled = !a.done; /* the daemon refuses a running one (409) */
    const actions = cell(show, 'actions');
    actions.append(del);
    tr.append(cell(time), cell(kind), what, cell(pill(status)), actions);
    return tr;
  }

  async function onShow(a) {
    const me = ++showing;
    clearBox();
    let op;
    try {
      op = await api.operation(a.id);
    } catch (e) {
      if (me !== showing) return;
      showError(box, e);
      if (e.status === 404) refresh(); /* deleted by another client */
      return;
    }
    if (me !== showing) return;
    formOf(a.kind).showStored(op);
  }

  async function onDelete(a, what) {
    if (!confirm(`Delete the stored ${what}?`)) return;
    clearBox();
    let gone = true;
    try {
      await api.deleteAnalysis(a.id);
    } catch (e) {
      showError(box, e); /* 409: it is running after all; 404: another client deleted it */
      gone = e.status === 404;
    }
    const form = formOf(a.kind);
    if (gone && form?.shown() === a.id) form.reset(); /* no result of a deleted analysis stays on screen */
    await refresh();
  }

  $('refresh-analyses').addEventListener('click', () => refresh());
  /* changed: a form's analysis started or ended */
  return { refresh, changed: () => refresh() };
}
