/*
 * session_stream.js — the open session's SSE stream into state.store, its
 * status pill, and the sample counter under the charts. The daemon ends a
 * stream when the session is not running; it reconnects only while a run of
 * this session is being polled (state.op). A stream the daemon refused (a
 * 503 while it restarts, say) is over: the pill says why until the next
 * start (a step, a run, rows the session list says are missing) opens a new
 * one, which replaces the message; a refused stream once kept its place and
 * its message, and no later run was streamed (review). A stream that ended
 * says why, from the session's status in the daemon's end event: "not
 * started" (created: nothing has run), "idle" (paused: a step, or a run
 * cancelled, can go on), "ended" only when the run is over (done, failed,
 * interrupted, deleted); a fresh session said "ended" (review).
 */
import { $ } from './dom.js';
import { streamSession } from './stream.js';
import { rowsOf } from './plots.js';
import { fmt } from './units.js';

/* What the pill says when the daemon ended the stream of a session with `status`. */
const END_LABEL = { created: 'not started', paused: 'idle' };
const endLabel = (status) => END_LABEL[status] || 'ended';

/* plots: the live charts (LivePlots), whose rows drawn the counter shows */
export function initSessionStream(state, plots) {
  /* Start streaming the open session's new rows, unless a stream is already on. */
  function start() {
    if (!state.session || state.stream) return;
    const id = state.session.id;
    const handle = streamSession(id, state.store, {
      onStatus: (st, detail) => {
        if (state.stream !== handle) return; /* a stopped stream's last words */
        if (st === 'error') pill(`error: ${detail.message}`, 'st-failed');
        else if (st === 'ended') pill(endLabel(detail ?? state.session?.status), 'muted');
        else pill(st, st === 'live' ? 'st-running' : 'muted');
        if (st === 'ended' || st === 'error') state.stream = null; /* over: the next start opens another */
      },
      isFinished: () => !(state.op && state.op.sessionId === id),
    });
    state.stream = handle;
  }

  function pill(text, cls) {
    const e = $('stream-status');
    e.textContent = `stream: ${text}`;
    e.className = `pill ${cls}`;
  }

  function stop() {
    state.stream?.stop();
    state.stream = null;
  }

  /* Stopped, and the status pill says so (no session open). */
  function clear() {
    stop();
    $('stream-status').textContent = 'no stream';
    $('stream-status').className = 'pill muted';
  }

  /* The session's samples (the last row's index + 1) and, when a long
   * history was thinned for the charts, how many of them are plotted: a reload
   * of a 180001-sample run said "45001 samples" (review). Counted as the
   * charts drew them (plots.drawnRows; the store's own rows before the
   * charts show it), so the counter and the charts tell the same t: called
   * after every redraw (main.js) and every 300 ms. */
  function updateCount() {
    const drawn = state.store && plots.drawnRows?.store === state.store ? plots.drawnRows : rowsOf(state.store);
    const n = drawn.rows;
    const stored = n ? Math.max(n, drawn.lastIndex + 1) : 0;
    const e = $('sample-count');
    const plural = (k) => `${k} sample${k === 1 ? '' : 's'}`;
    e.textContent = `${plural(stored)}${n ? ` · t = ${fmt(drawn.t)} s` : ''}${stored > n ? ` · ${n} plotted (history thinned)` : ''}`;
    e.dataset.count = String(n);
  }

  return { start, stop, clear, updateCount };
}
