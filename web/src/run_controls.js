/*
 * run_controls.js — Step, Run to end and Cancel for the open session, and
 * the polling of a run's long-running operation (state.op) that moves the
 * header and progress bar until the run is done, failed or cancelled. An
 * answer that arrives after the polling stopped (another session opened, or
 * another run followed) is dropped.
 */
import { api, ApiError } from './api.js';
import { $ } from './dom.js';
import { hideError, showError, showSessionError } from './messages.js';
import { fmt } from './units.js';
import { markFromProblem, numberField } from './number_input.js';
import { followOperation, operationError, outcomeOf, outcomeSuffix } from './operation.js';

export function initRunControls(state, { header, stream, refreshList }) {
  /* at least one sample period of the open session (a shorter step stores nothing) */
  const stepDuration = numberField($('step-duration'), () => {
    const rate = state.session?.config?.run?.sample_rate || state.session?.sample_rate;
    return rate > 0 ? { name: 'step duration [s]', min: 1 / rate, note: `one sample period, 1 / ${fmt(rate)} Hz` } : { name: 'step duration [s]', above: 0 };
  });

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
      /* the daemon names the field (off the sample grid, longer than --max-step): mark it too */
      markFromProblem(e, { '/duration': $('step-duration') });
      /* the daemon's advice names its API (POST .../run); here that is the Run
       * button: the message is written from the problem's fields, not its text */
      const p = e instanceof ApiError ? e.problem : null;
      if (p?.type === '/problems/step-too-long' && typeof p.max_duration === 'number') {
        const m = `/duration: a step is at most ${fmt(p.max_duration)} s, got ${fmt(duration)} s; use Run to end for longer advances`;
        e = new ApiError(e.status, { ...p, detail: m, errors: [{ pointer: '/duration', message: m }] });
      }
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
    state.op?.follower?.stop(); /* null while followOperation is still calling back */
    state.op = null;
  }

  /* Follow operation `id` of the open session; `first`: the operation itself when already at hand. */
  function poll(id, first) {
    stop();
    const me = { id, sessionId: state.session.id, meta: null, follower: null };
    state.op = me;
    delete $('progress-text').dataset.outcome;
    header.render();
    me.follower = followOperation(id, first, 300, {
      async error(e) {
        stop();
        /* the operation is gone (a restarted daemon): the session says how its run ended */
        await header.refresh();
        if (state.session && state.session.status !== 'running') showSessionError($('session-error'), state.session);
        else showError($('session-error'), e);
        stream.start();
        refreshList();
      },
      unreachable(e, wait) {
        const again = `trying again in ${fmt(wait / 1000)} s`;
        showError($('session-error'), new ApiError(e.status, { ...e.problem, detail: e.problem.detail ? `${e.problem.detail} (${again})` : again }));
      },
      reached() {
        hideError($('session-error')); /* it said the daemon could not be reached */
      },
      async done(op) {
        stop();
        const m = op.metadata || {};
        const outcome = outcomeOf(op.error);
        if (outcome === 'failed' || outcome === 'interrupted') showError($('session-error'), operationError(op));
        await header.refresh();
        header.renderProgress(m);
        const end = outcomeSuffix(outcome);
        if (end) $('progress-text').textContent += ` · ${end}`;
        $('progress-text').dataset.outcome = outcome;
        stream.start(); /* catch up on rows stored after the stream last closed */
        refreshList();
      },
      progress(op) {
        const m = op.metadata || {};
        me.meta = m;
        if (typeof m.t === 'number') Object.assign(state.session, { status: 'running', t: Math.max(m.t, state.session.t || 0) });
        header.render();
      },
    });
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
