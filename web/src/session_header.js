/*
 * session_header.js — the open session's header: title, status, the meta
 * line, which run buttons are enabled, and the progress bar (t / run
 * duration). Drawn from state.session and state.op; refresh() re-reads the
 * session from the daemon first.
 */
import { api } from './api.js';
import { channelsOf } from './channels.js';
import { $, setBar, shortId } from './dom.js';
import { showError } from './messages.js';
import { fmt, fmtTime } from './units.js';

export function initSessionHeader(state) {
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
          `t = ${fmtTime(s.t || 0, s.config?.run?.sample_rate)} s${dur ? ` of ${fmtTime(dur, s.config?.run?.sample_rate)} s` : ''}`,
          s.error ? `error: ${s.error}` : '',
        ]
          .filter(Boolean)
          .join(' · ')
      : gone || '';
    const running = s?.status === 'running' || !!state.op;
    const ended = open && dur !== undefined && (s.t || 0) >= dur - 1e-9;
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
    if (dur) setProgress((state.session.t || 0) / dur, meta);
    else resetProgress();
  }

  function setProgress(frac, meta) {
    const pct = Math.max(0, Math.min(100, frac * 100));
    setBar($('run-progress'), pct, 1);
    let txt = `${pct.toFixed(pct >= 99.95 || pct === 0 ? 0 : 1)} %`;
    if (meta?.t !== undefined) txt += ` · t = ${fmtTime(meta.t, state.session?.config?.run?.sample_rate)} s`;
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

  return { render, renderProgress, refresh };
}
