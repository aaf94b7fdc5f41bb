/*
 * operation.js — following one long-running operation of the daemon (a
 * session's run, an analysis): poll GET /v1/operations/{id} until it is
 * done. Shared by run_controls.js and analysis_op.js, which differ only in
 * what they draw. After stop() no callback runs, also for an answer already
 * on its way. A poll that fails for a passing reason (transient: the daemon
 * restarting, a proxy's 502 / 503 / 504) is tried again with backoff until
 * followLimits.patience has passed without an answer; any other failure (a
 * 4xx: the operation is gone, the token was rejected) ends the following.
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

/* What a progress line ends with for an outcome ('' while running or when done):
 * an ended one's, or the follower's own (reconnecting: polls fail for a passing
 * reason and are tried again; lost: it gave up, see followOperation). */
const SUFFIX = new Map([...['cancelled', 'failed', 'interrupted', 'refused', 'reconnecting'].map((w) => [w, w]), ['lost', 'connection lost']]);
export const outcomeSuffix = (outcome) => SUFFIX.get(outcome) || '';

/* A failed poll worth trying again: the daemon could not be reached (status 0:
 * a restart, a dropped connection) or a proxy or the daemon says it is away
 * for now (502, 503: also a draining daemon, 504). */
const transient = (e) => [0, 502, 503, 504].includes(e?.status);

/* [ms] The backoff's cap and how long polls may fail before the follower gives
 * up (the browser test shortens patience through tanksimDebug). */
export const followLimits = { maxBackoff: 5000, patience: 60000 };

/**
 * Follow operation `id` every `period` ms; `first`: the operation itself when
 * already at hand (a POST answers with it). on.progress(op) for each answer
 * not yet done, on.done(op) once at the end, on.error(e) when a poll fails
 * for good (the following then ends). A transient failure is told to
 * on.unreachable(e, wait) (optional) and polled again after `wait` ms (period,
 * doubled each time up to followLimits.maxBackoff); on.reached() (optional)
 * hears of the next answer. When polls have failed for followLimits.patience
 * ms, on.error gets an ApiError with lost = true that says so (the operation
 * may well still run). Returns { stop() }.
 */
export function followOperation(id, first, period, on) {
  let timer = null;
  let stopped = false;
  let wait = 0; /* [ms] the backoff while polls fail (0: the last was answered) */
  let since = 0; /* [ms, Date.now()] the first of the polls failing since the last answer */
  const tick = async (op) => {
    try {
      op = op || (await api.operation(id));
    } catch (e) {
      if (stopped) return;
      if (transient(e)) {
        const now = Date.now();
        since = since || now;
        if (now - since < followLimits.patience) {
          wait = Math.min(followLimits.maxBackoff, wait ? wait * 2 : period);
          on.unreachable?.(e, wait);
          if (!stopped) timer = setTimeout(() => tick(), wait);
          return;
        }
        e = lostError(id, e, now - since);
      }
      stopped = true;
      on.error(e);
      return;
    }
    if (stopped) return;
    if (wait) {
      wait = 0;
      since = 0;
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

/* The error the follower gives up with: no answer for `ms` ms, the last failure e. */
function lostError(id, e, ms) {
  const err = new ApiError(e.status, {
    title: 'Lost contact with the daemon',
    detail: `no answer about operation ${id} for ${Math.round(ms / 1000)} s (last: ${e.message}); it may still be running: the daemon keeps its outcome`,
  });
  err.lost = true;
  return err;
}
