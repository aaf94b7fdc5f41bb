/*
 * session_list.js — the sessions table (GET /v1/sessions, all pages), drawn
 * again on every refresh: a row's id button (or a click anywhere on the row)
 * opens its session, its checkbox ticks it for Compare (a session gone from the list is unticked). An empty table says
 * why (none yet, or the daemon refused; a 401 also asks for the token).
 */
import { allSessions, getToken } from './api.js';
import { $, cell, pill, shortId } from './dom.js';
import { askForToken } from './messages.js';
import { fmt } from './units.js';

/* Why the list is empty: no sessions, or the daemon refused to list them. */
function listMessage(e) {
  if (!e) return 'No sessions yet — create one below.';
  if (e.status !== 401) return `Could not load the sessions: ${e.message}`;
  return getToken()
    ? 'Token rejected: the daemon did not accept the saved API token. Enter the right one under “API token” at the top and press Save.'
    : 'Authentication required: the daemon was started with an API token. Enter it under “API token” at the top and press Save.';
}

const text = (s) => document.createTextNode(s);

/* view: the open session's {open, snapshot, follow} (session_view.js); ticksChanged: after state.compare changed. */
export function initSessionList(state, { view, ticksChanged }) {
  async function refresh() {
    const tbody = $('session-table').querySelector('tbody');
    const seen = view.snapshot();
    let sessions;
    try {
      sessions = await allSessions();
    } catch (e) {
      if (e.status === 401) askForToken();
      tbody.replaceChildren();
      $('sessions-empty').textContent = listMessage(e);
      $('sessions-empty').dataset.problem = String(e.status ?? '');
      $('sessions-empty').hidden = false;
      return;
    }
    $('sessions-empty').textContent = listMessage(null);
    delete $('sessions-empty').dataset.problem;
    /* the redraw replaces the rows: a keyboard user's focus goes back where it was */
    const had = tbody.contains(document.activeElement) ? document.activeElement : null;
    const focus = had && { id: had.closest('tr')?.dataset.id, cmp: had.classList.contains('cmp') };
    tbody.replaceChildren();
    for (const s of sessions) {
      const tr = document.createElement('tr');
      const short = shortId(s.id);
      tr.dataset.id = s.id;
      if (state.session && state.session.id === s.id) tr.classList.add('selected');
      const cb = document.createElement('input');
      cb.type = 'checkbox';
      cb.className = 'cmp';
      cb.checked = state.compare.has(s.id);
      cb.title = 'include in Compare';
      cb.setAttribute('aria-label', `include session ${short} in Compare`);
      cb.addEventListener('click', (ev) => ev.stopPropagation());
      cb.addEventListener('change', () => {
        if (cb.checked) state.compare.add(s.id);
        else state.compare.delete(s.id);
        ticksChanged();
      });
      /* keyboard and screen readers: the id is the row's one control that opens
       * it (the row itself is not focusable: it would hold the checkbox) */
      const open = document.createElement('button');
      open.type = 'button';
      open.className = 'open-session mono';
      open.textContent = short;
      open.setAttribute('aria-label', `open session ${short}, ${s.preset || 'no preset'}, ${s.status}`);
      const cells = [
        cb,
        open,
        text(s.preset || '—'),
        pill(s.status),
        text(s.t !== undefined ? `${fmt(s.t, 4)}${s.duration ? ` / ${fmt(s.duration)}` : ''}` : '—'),
      ];
      cells.forEach((c, i) => tr.append(cell(c, i === 4 ? 'num' : undefined)));
      tr.addEventListener('click', () => view.open(s.id)); /* the button's click bubbles here */
      tbody.append(tr);
      /* the poll must not scroll the page back to a row the user scrolled away from */
      if (focus && focus.id === s.id) (focus.cmp ? cb : open).focus({ preventScroll: true });
    }
    $('sessions-empty').hidden = sessions.length > 0;
    const ticked = state.compare.size;
    for (const id of state.compare) if (!sessions.some((s) => s.id === id)) state.compare.delete(id);
    if (state.compare.size !== ticked) ticksChanged(); /* else compare-info keeps what the last overlay said */
    view.follow(seen, sessions);
  }

  $('refresh-sessions').addEventListener('click', refresh);

  return { refresh };
}
