/*
 * run_controls.js — Step, Run to end and Cancel for the open session, and
 * the polling of a run's long-running operation (state.op) that moves the
 * header and progress bar until the run is done, failed or cancelled. An
 * answer that arrives after the polling stopped (another session opened, or
 * another run followed) is dropped.
 */
import { api, ApiError } from './api.js';
import { $ } from './dom.js';
import { hideError, showError } from './messages.js';
import { numberField } from './number_input.js';

/* google.rpc code 1 = CANCELLED (the daemon also sends a problem type). */
const isCancelled = (err) => err.code === 1 || /cancel/i.test(err.type || '');

export function initRunControls(state, { header, stream, refreshList }) {
  const stepDuration = numberField($('step-duration'), { name: 'step duration [s]', above: 0 });

  async function onStep() {
    const s = state.session;
    hideError($('session-error'));
    const { value: duration, error } = stepDuration();
    try {
      if (error) throw new ApiError(0, { title: 'Not stepped', detail: error });
      await api.step(s.id, duration); /* synchronous: the answer is the session's new state */
      await header.refresh();
      stream.start(); /* fetch the new rows (the stream ends when they are sent) */
      refreshList();
    } catch (e) {
      showError($('session-error'), e);
    }
  }

  async function onRun() {
    const s = state.session;
    hideError($('session-error'));
    try {
      const pace = Number($('run-pace').value) || undefined;
      const op = await api.run(s.id, s.config?.run?.duration, pace);
      poll(op.id, op);
      stream.start();
    } catch (e) {
      showError($('session-error'), e);
    }
  }

  function stop() {
    if (state.op) clearTimeout(state.op.timer);
    state.op = null;
  }

  /* Follow operation `id` of the open session; `first`: the operation itself when already at hand. */
  function poll(id, first) {
    stop();
    const me = { id, sessionId: state.session.id, timer: null, meta: null };
    state.op = me;
    delete $('progress-text').dataset.outcome;
    header.render();
    /* stop() clears the timer, but not an answer already on its way */
    const tick = async (op) => {
      try {
        op = op || (await api.operation(id));
      } catch (e) {
        if (state.op !== me) return;
        showError($('session-error'), e);
        stop();
        header.render();
        return;
      }
      if (state.op !== me) return;
      const m = op.metadata || {};
      if (op.done) {
        stop();
        const cancelled = op.error && isCancelled(op.error);
        if (op.error && !cancelled) showError($('session-error'), new ApiError(op.error.status || 500, op.error));
        await header.refresh();
        header.renderProgress(m);
        if (cancelled) $('progress-text').textContent += ' · cancelled';
        $('progress-text').dataset.outcome = cancelled ? 'cancelled' : op.error ? 'failed' : 'done';
        stream.start(); /* catch up on rows stored after the stream last closed */
        refreshList();
        return;
      }
      me.meta = m;
      if (typeof m.t === 'number') Object.assign(state.session, { status: 'running', t: Math.max(m.t, state.session.t || 0) });
      header.render();
      me.timer = setTimeout(() => tick(), 300);
    };
    tick(first); /* POST run answers with the operation itself */
  }

  async function onCancel() {
    if (!state.op) return;
    try {
      await api.cancel(state.op.id);
    } catch (e) {
      showError($('session-error'), e);
    }
  }

  $('step-btn').addEventListener('click', onStep);
  $('run-btn').addEventListener('click', onRun);
  $('cancel-btn').addEventListener('click', onCancel);

  return { poll, stop };
}
