/*
 * session_header.js — the open session's header: title, status, the meta
 * line, which run buttons are enabled, and the progress bar (t / run
 * duration). Drawn from state.session and state.op; refresh() re-reads the
 * session from the daemon first. Its t is never less than that of the rows
 * the live charts drew (rowsDrawn, told after each redraw): it was the run
 * operation's t, polled every 300 ms, and showed up to a second of a 5x run
 * less than the charts (review).
 */
import { api } from './api.js';
import { channelsOf } from './channels.js';
import { $, setBar, shortId } from './dom.js';
import { showError } from './messages.js';
import { fmt, fmtTime } from './units.js';

export function initSessionHeader(state) {
  let drawn = { id: null, t: 0 }; /* the last row the charts drew, of session id */

  /* The session's t as shown: its own (the daemon's, the run operation's) or the charts' last row's.
   * By id, as run_figures.js: a refresh reads the session into a new object. */
  const tOf = (s) => Math.max(s?.t || 0, s && drawn.id === s.id ? drawn.t : 0);

  /* The live charts drew rows of the open session up to t: the header follows when that is further. */
  function rowsDrawn(t) {
    const s = state.session;
    if (!s || typeof t !== 'number' || !(t > tOf(s))) return;
    drawn = { id: s.id, t };
    render();
  }

  /* Title, status, time, buttons and progress of the open session; `gone`: what to say when none is. */
  function render(gone) {
    const s = state.session;
    const open = !!s;
    $('session-title').textContent = open ? `Session ${shortId(s.id)}` : 'No session open';
    const st = $('session-status');
    const status = s?.status || (gone ? 'deleted' : '');
    st.className = `pill st-${status || 'none'}`;
    st.textContent = status;
    const dur = s?.config?.run?.duration;
    const kind = s?.config?.run?.kind;
    /* the track's fidelity where the run has a track (its channels say so) */
    const fid = open && channelsOf(s).some((c) => c.name.startsWith('track.')) ? s.config?.track?.fidelity : undefined;
    $('session-meta').textContent = open
      ? [
          `preset ${s.preset || '—'}`,
          kind && `scenario ${kind}`,
          fid && `track ${fid}`,
          `t = ${fmtTime(tOf(s), s.config?.run?.sample_rate)} s${dur ? ` of ${fmtTime(dur, s.config?.run?.sample_rate)} s` : ''}`,
          s.error ? `error: ${s.error}` : '',
        ]
          .filter(Boolean)
          .join(' · ')
      : gone || '';
    const running = s?.status === 'running' || !!state.op;
    const ended = open && dur !== undefined && tOf(s) >= dur - 1e-9;
    $('step-btn').disabled = !open || running || ended;
    $('run-btn').disabled = !open || running || ended;
    $('cancel-btn').disabled = !state.op;
    $('delete-session').disabled = !open;
    renderProgress(state.op?.meta);
  }

  /* The bar shows t / run duration (meta: the run operation's metadata, for
   * its speed), not the operation's own progress: that restarts at 0 when a
   * paused run continues, t / duration only moves forward. */
  function renderProgress(meta) {
    const dur = state.session?.config?.run?.duration;
    if (dur) setProgress(tOf(state.session) / dur, meta);
    else resetProgress();
  }

  function setProgress(frac, meta) {
    const pct = Math.max(0, Math.min(100, frac * 100));
    setBar($('run-progress'), pct, 1);
    let txt = `${pct.toFixed(pct >= 99.95 || pct === 0 ? 0 : 1)} %`;
    /* the run's t: its operation's, or the charts' when they drew further */
    if (meta?.t !== undefined) txt += ` · t = ${fmtTime(Math.max(meta.t, tOf(state.session)), state.session?.config?.run?.sample_rate)} s`;
    if (meta?.real_time_factor) txt += ` · ${fmt(meta.real_time_factor, 3)}× real time`;
    $('progress-text').textContent = txt;
  }

  function resetProgress() {
    setBar($('run-progress'), null);
    $('progress-text').textContent = '—';
    delete $('progress-text').dataset.outcome;
  }

  /* GET the open session again and show it. */
  async function refresh() {
    if (!state.session) return;
    try {
      const s = await api.session(state.session.id);
      if (!state.session || s.id !== state.session.id) return;
      state.session = s;
      render();
    } catch (e) {
      showError($('session-error'), e);
    }
  }

  return { render, renderProgress, refresh, rowsDrawn };
}
