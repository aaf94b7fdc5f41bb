/*
 * analysis_op.js — the operation of one analysis form (POST /v1/engine-map,
 * POST /v1/tune): Run starts it, polling GET /v1/operations/{id} moves the
 * form's progress bar (parts_done / parts_total), Cancel asks the daemon to
 * stop it after the part in progress, and the response goes to onDone. The
 * operation polled is state.analyses[kind]; an answer that arrives after it
 * was replaced is dropped. A refusal (400, 429: one analysis at a time) or
 * a failed or interrupted (the daemon stopped) operation is shown in the
 * form's error box in the daemon's words; the progress bar says "refused"
 * for the first (nothing ran), "failed" or "interrupted" for the others.
 * While polls fail for a passing reason (the daemon restarting, a proxy's
 * 502 / 503: operation.js) the bar says "reconnecting" and when the next try
 * is, keeping the parts done; the result is still shown when the daemon
 * answers again. After followLimits.patience without an answer the form
 * gives up: "connection lost" on the bar, the reason in the error box.
 * changed() hears of each start and end (the stored-analyses list,
 * stored_analyses.js); showStored(op) shows a stored analysis the list hands
 * over as the form shows its own (a cancel there is an error: the daemon's
 * words, not this page's doing), on the progress bar unless the form's own
 * one runs. The form's result is taken away (onClear) when a run starts and
 * before an ended one is shown; shown() is the id of the analysis whose
 * result is on screen, reset() takes it away (it was deleted).
 *
 * Run stays disabled while the form's preset list is empty (presetsSet: the
 * list came): a click before GET /v1/presets answered sent preset "" (404).
 *
 * Elements, by the form's prefix p: p-run, p-cancel, p-error, p-preset,
 * p-progress (data-percent, data-outcome; the bar: its .bar), p-progress-text.
 */
import { api } from './api.js';
import { $, setBar } from './dom.js';
import { hideError, showError } from './messages.js';
import { followOperation, operationError, outcomeOf, outcomeSuffix } from './operation.js';
import { fmt } from './units.js';

/**
 * kind: the key in state.analyses; prefix: the form's element ids; onDone(response):
 * draw the result (may throw an ApiError: shown as the form's error); onClear(): take
 * the result off screen; changed() (optional): an operation started or ended.
 * Returns {start(begin), showStored(op), attach(id), reset(), presetsSet(), shown()}: begin() sends the
 * request and resolves to the operation; op: a done operation (GET /v1/operations/{id});
 * attach follows a running operation the page did not start; reset takes the result
 * shown and the progress bar away; shown: the id of the analysis whose result is shown
 * (null: none).
 */
export function initAnalysisOp(state, kind, prefix, { onDone, onClear, changed = () => {} }) {
  const el = (name) => $(`${prefix}-${name}`);
  const box = el('error');
  let shownId = null; /* the analysis whose result is on screen */

  /* The bar at meta's parts; outcome: how it ended, or the follower's state (outcomeSuffix); note: said after it. */
  function render(meta, outcome, note) {
    const total = meta?.parts_total;
    const done = meta?.parts_done ?? 0;
    const pct = total ? Math.round((100 * done) / total) : null;
    setBar(el('progress'), pct);
    if (outcome) el('progress').dataset.outcome = outcome;
    else delete el('progress').dataset.outcome;
    const parts = total ? `${done} / ${total} parts · ${pct} %` : '';
    el('progress-text').textContent = [parts, outcomeSuffix(outcome), note].filter(Boolean).join(' · ') || '—';
    setButtons();
  }

  /* Run while nothing runs and a preset is chosen, Cancel while one runs;
     also when the preset list was filled (presetsSet) */
  function setButtons() {
    const running = state.analyses[kind] !== null;
    el('run').disabled = running || !el('preset').value;
    el('cancel').disabled = !running;
  }

  function clear() {
    onClear();
    shownId = null;
  }

  /* Show ended operation `op` in place of the last result: its response drawn,
     or its error in the daemon's words (a cancel only when cancelShown). Returns
     its outcome ('failed' when onDone could not draw it). */
  function showEnded(op, cancelShown) {
    clear();
    let outcome = outcomeOf(op.error);
    try {
      /* failed or interrupted: the daemon's words (the latter say to start it again) */
      if (op.error && (cancelShown || outcome !== 'cancelled')) throw operationError(op);
      if (outcome === 'done') onDone(op.response);
    } catch (e) {
      if (outcome === 'done') outcome = 'failed'; /* onDone could not draw it */
      showError(box, e);
    }
    if (outcome === 'done') shownId = op.id;
    return outcome;
  }

  function stop() {
    state.analyses[kind]?.follower?.stop(); /* null while followOperation is still calling back */
    state.analyses[kind] = null;
  }

  async function start(begin) {
    hideError(box);
    stop();
    clear(); /* the last result is not the answer to this request */
    render(null);
    el('run').disabled = true; /* until the daemon answers */
    let op;
    try {
      op = await begin();
    } catch (e) {
      showError(box, e);
      render(null, 'refused'); /* nothing ran: the daemon's reason is in the error box */
      return;
    }
    changed();
    follow(op.id, op);
  }

  /* Follow operation `id` (`first`: the operation itself when at hand). */
  function follow(id, first) {
    const me = { id, follower: null, meta: first?.metadata }; /* meta: the last answer's */
    state.analyses[kind] = me;
    render(me.meta);
    me.follower = followOperation(id, first, 200, {
      error(e) {
        stop();
        showError(box, e);
        render(e.lost ? me.meta : null, e.lost ? 'lost' : 'failed'); /* lost: the parts it last heard of */
        changed();
      },
      unreachable(e, wait) {
        render(me.meta, 'reconnecting', `next try in ${fmt(wait / 1000)} s`);
      },
      reached() {
        render(me.meta); /* the answer's own render follows */
      },
      done(cur) {
        stop();
        render(cur.metadata, showEnded(cur, false)); /* a cancel: this page's or another client's doing, not an error */
        changed();
      },
      progress(cur) {
        me.meta = cur.metadata;
        render(me.meta);
      },
    });
  }

  async function onCancel() {
    const me = state.analyses[kind];
    if (!me) return;
    try {
      await api.cancel(me.id);
    } catch (e) {
      showError(box, e);
    }
  }

  function showStored(op) {
    hideError(box);
    const outcome = showEnded(op, true); /* a cancel too: not this page's doing */
    if (!state.analyses[kind]) render(op.metadata, outcome); /* else the bar is the running one's */
  }

  /* Follow running analysis `id` that this page did not start (one still
     running when the page was loaded): progress, Cancel and its result as
     for the form's own; nothing when the form already follows one. */
  function attach(id) {
    if (state.analyses[kind]) return;
    hideError(box);
    follow(id, null);
  }

  /* The result shown and the progress bar back to "—" (the analysis they showed was deleted), the bar unless one runs. */
  function reset() {
    clear();
    if (!state.analyses[kind]) render(null);
  }

  el('cancel').addEventListener('click', onCancel);
  render(null);
  return { start, showStored, attach, reset, presetsSet: setButtons, shown: () => shownId };
}
