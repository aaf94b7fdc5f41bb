/*
 * operation.js — following one long-running operation of the daemon (a
 * session's run, an analysis): poll GET /v1/operations/{id} until it is
 * done. Shared by run_controls.js and analysis_op.js, which differ only in
 * what they draw. After stop() no callback runs, also for an answer already
 * on its way.
 */
import { api, ApiError } from './api.js';

/* How a finished operation ended, from its error member (google.rpc code;
 * the daemon also sends a problem type): 'done' (none), 'cancelled' (1, a
 * client's cancel), 'interrupted' (14, the daemon stopped during it: a
 * shutdown, or a crash found at its next start) or 'failed'. */
export function outcomeOf(err) {
  if (!err) return 'done';
  if (err.code === 1 || /cancel/i.test(err.type || '')) return 'cancelled';
  if (err.code === 14 || /interrupted/i.test(err.type || '')) return 'interrupted';
  return 'failed';
}

/* The error an ended operation carries, as an ApiError (null when it succeeded). */
export const operationError = (op) => (op.error ? new ApiError(op.error.status || 500, op.error) : null);

/* The word a progress line ends with for an outcome ('' while running or when done). */
export const outcomeSuffix = (outcome) => (['cancelled', 'failed', 'interrupted', 'refused'].includes(outcome) ? outcome : '');

/**
 * Follow operation `id` every `period` ms; `first`: the operation itself when
 * already at hand (a POST answers with it). on.progress(op) for each answer
 * not yet done, on.done(op) once at the end, on.error(e) when a poll fails
 * (the following then ends). With on.unreachable(e) a poll that could not
 * reach the daemon (ApiError status 0) is told there instead and polled
 * again with backoff (up to MAX_BACKOFF ms); on.reached() hears of the next
 * answer. Returns { stop() }.
 */
const MAX_BACKOFF = 5000;

export function followOperation(id, first, period, on) {
  let timer = null;
  let stopped = false;
  let wait = 0; /* [ms] the backoff while the daemon is unreachable (0: it answers) */
  const tick = async (op) => {
    try {
      op = op || (await api.operation(id));
    } catch (e) {
      if (stopped) return;
      if (on.unreachable && e.status === 0) {
        wait = Math.min(MAX_BACKOFF, wait ? wait * 2 : period);
        on.unreachable(e, wait);
        if (!stopped) timer = setTimeout(() => tick(), wait);
        return;
      }
      stopped = true;
      on.error(e);
      return;
    }
    if (stopped) return;
    if (wait) {
      wait = 0;
      on.reached?.();
    }
    if (op.done) {
      stopped = true;
      await on.done(op);
      return;
    }
    on.progress(op);
    if (!stopped) timer = setTimeout(() => tick(), period);
  };
  tick(first);
  return {
    stop() {
      stopped = true;
      clearTimeout(timer);
    },
  };
}
