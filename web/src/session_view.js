/*
 * session_view.js — the open session (state.session): open it (history,
 * charts, every panel, a run in progress followed), close it (every panel
 * drops its data), delete it, and keep it in step with the polled session
 * list when another client runs or deletes it. The open session's id is kept
 * in the page's address (page_state.js): a reload opens it again.
 */
import { api } from './api.js';
import { $ } from './dom.js';
import { hideError, showError, showSessionError } from './messages.js';
import { SeriesStore } from './stream.js';
import { defaultPicks } from './plots.js';
import { channelsOf } from './channels.js';
import { writePageState } from './page_state.js';

/* long histories are thinned to about this many rows; live rows come at full rate */
const HISTORY_POINTS = 50000;

export function initSessionView(state, { plots, frames, header, stream, picker, fftControls, compareControls, figures, run, refreshList }) {
  /* The open session's row in the list is highlighted (none when none is open). */
  function markRow() {
    for (const tr of $('session-table').querySelectorAll('tr[data-id]')) tr.classList.toggle('selected', tr.dataset.id === state.session?.id);
  }

  async function open(id, given) {
    hideError($('session-error'));
    let s = given;
    try {
      if (!s || !s.channels) s = await api.session(id);
    } catch (e) {
      showError($('session-error'), e);
      return;
    }
    stream.stop();
    run.stop();
    state.session = s;
    writePageState({ session: s.id }); /* a reload opens it again */
    markRow();
    header.render();
    /* on a narrow page the session panel sits below the whole create form:
     * bring it into view, or opening a session seemed to do nothing (review) */
    const panel = $('session-panel');
    if (panel.getBoundingClientRect().top > window.innerHeight) panel.scrollIntoView({ block: 'start' });
    const chans = channelsOf(s);
    state.store = new SeriesStore(chans);
    state.picks = defaultPicks(chans);
    picker.render();
    fftControls.open(chans);
    figures.open();
    try {
      const every = Math.max(1, Math.ceil((s.index || 0) / HISTORY_POINTS));
      if ((s.t || 0) > 0 || (s.index || 0) > 0) await state.store.loadHistory(s.id, every);
    } catch (e) {
      showError($('session-error'), e);
    }
    if (state.session !== s) return; /* another session was opened meanwhile */
    $('plots-empty').hidden = true;
    plots.show(state.store, state.picks);
    stream.updateCount();
    fftControls.update();
    frames.setSession(s);
    compareControls.updateChannels();
    stream.start();
    if (s.status === 'running' && s.operation) run.poll(s.operation);
  }

  /* No session open any more (`notice` says why): every panel drops its data. */
  function close(notice) {
    const id = state.session?.id;
    stream.clear();
    run.stop();
    state.session = null;
    writePageState({ session: null });
    state.store = null;
    state.picks = [];
    plots.stop();
    frames.clear();
    fftControls.close();
    figures.clear();
    compareControls.close(id);
    hideError($('session-error'));
    $('plots-empty').hidden = false;
    picker.clear();
    markRow();
    header.render(notice);
    stream.updateCount();
  }

  async function onDelete() {
    const s = state.session;
    if (!s || !confirm(`Delete session ${s.id}?`)) return;
    try {
      await api.deleteSession(s.id);
    } catch (e) {
      if (e.status !== 404) {
        showError($('session-error'), e);
        return;
      }
    }
    close(`Session ${s.id} was deleted.`);
    refreshList();
  }

  /* What the open session looked like when a list request left. */
  function snapshot() {
    const s = state.session;
    return s && { s, status: s.status, t: s.t, op: state.op };
  }

  /* Keep the open session in step with the list `sessions` (a run or a
   * delete by another client), unless it changed here while the list was on
   * its way (then the list is the older news) or an operation's polling
   * already follows it. */
  function follow(seen, sessions) {
    const s = state.session;
    if (!s || !seen || seen.s !== s || seen.status !== s.status || seen.t !== s.t || seen.op || state.op) return;
    const sum = sessions.find((x) => x.id === s.id);
    if (!sum) {
      close(`Session ${s.id} no longer exists (deleted).`);
      return;
    }
    const lagging = behind(sum);
    if (sum.status === s.status && sum.t === s.t && !lagging) return;
    const statusChanged = sum.status !== s.status;
    Object.assign(s, { status: sum.status, t: sum.t, index: sum.index, error: sum.error, operation: sum.operation });
    header.render();
    /* the daemon's reason (an interrupted run) replaces what the box said about the old status */
    if (statusChanged) showSessionError($('session-error'), s);
    if (sum.status === 'running' && sum.operation) run.poll(sum.operation);
    /* rows stored by another client's step or run: the stream sends them from the
     * store's last index and ends when the session is not running */
    if (lagging || sum.status === 'running') stream.start();
  }

  /* The list's summary has rows the store does not. */
  const behind = (sum) => !!state.store && (sum.samples || 0) > 0 && typeof sum.index === 'number' && sum.index > state.store.lastIndex;

  $('delete-session').addEventListener('click', onDelete);

  return { open, snapshot, follow };
}
