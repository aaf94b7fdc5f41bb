/*
 * compare_controls.js — the Compare panel's controls: the sessions ticked in
 * the list (state.compare), the channel to overlay, and the Compare button
 * that draws them with ComparePanel (compare.js).
 */
import { api, ApiError } from './api.js';
import { $, shortId } from './dom.js';
import { hideError, showError } from './messages.js';
import { channelsOf, fillChannelSelect } from './channels.js';

/* Every channel of the sessions, each name once, in first-seen order. */
function unionChannels(sessions) {
  const chans = [];
  for (const s of sessions) for (const c of channelsOf(s)) if (!chans.some((x) => x.name === c.name)) chans.push(c);
  return chans;
}

export function initCompareControls(state, compare) {
  let filled = 0; /* the latest channel-list refresh: one answering late is dropped */

  const ticked = () => Promise.all([...state.compare].map((id) => api.session(id)));
  /* A session's channel list is fixed at its creation: fetched once per id
   * for the channel select (the Compare button still fetches them fresh),
   * kept while the session is ticked (the list unticks a deleted one). An
   * entry is its fetch (a promise of {channels}), in the map from the moment
   * it is sent: unticking deletes it, and an answer that comes after that
   * adds nothing back (it once stored the unticked session again); a fetch
   * that fails takes away its own entry only, not a newer one. */
  const channelsKnown = new Map();
  const forgetUnticked = () => {
    for (const id of channelsKnown.keys()) if (!state.compare.has(id)) channelsKnown.delete(id);
  };
  function channelsFor(id) {
    let entry = channelsKnown.get(id);
    if (!entry) {
      entry = api.session(id).then((s) => ({ channels: s.channels }));
      channelsKnown.set(id, entry);
      entry.catch(() => channelsKnown.get(id) === entry && channelsKnown.delete(id));
    }
    return entry;
  }
  const tickedChannels = () => Promise.all([...state.compare].map(channelsFor));

  /* List the channels the sessions have, the one chosen kept while it is still there; returns the choice. */
  function listChannels(sessions) {
    const sel = $('compare-channel');
    fillChannelSelect(sel, unionChannels(sessions), sel.value || state.picks[0]);
    return sel.value;
  }

  /* The channel list follows the ticked sessions (the open session while none
     is ticked): a ticked accel run lists engine.speed even when a bump-course
     session is open. */
  async function updateChannels() {
    const me = ++filled;
    forgetUnticked();
    let sessions;
    try {
      sessions = state.compare.size ? await tickedChannels() : [state.session].filter(Boolean);
    } catch {
      return; /* a ticked session went: Compare says so when asked */
    }
    if (me === filled) listChannels(sessions);
  }

  function updateInfo() {
    const n = state.compare.size;
    $('compare-info').textContent = n ? `${n} session${n > 1 ? 's' : ''} ticked` : 'none ticked';
    updateChannels();
  }

  async function onCompare() {
    const box = $('compare-error');
    hideError(box);
    if (state.compare.size < 1) {
      showError(box, new ApiError(0, { title: 'Nothing to compare', detail: 'tick sessions in the list (cmp column) first' }));
      return;
    }
    try {
      const sessions = await ticked();
      const channel = listChannels(sessions);
      const r = await compare.show(sessions, channel);
      const lacking = r.missing.map((s) => shortId(s.id)).join(', ');
      $('compare-info').textContent = `${r.series} session${r.series > 1 ? 's' : ''} overlaid${lacking ? ` · not plotted, no channel ${channel}: ${lacking}` : ''}`;
    } catch (e) {
      compare.clear(); /* an overlay of an earlier request would pass for this one */
      showError(box, e);
    }
  }

  /* Session `id` was closed: an overlay that shows it goes. */
  function close(id) {
    if (compare.shows(id)) compare.clear();
  }

  $('compare-btn').addEventListener('click', onCompare);
  updateInfo();

  /* cached(): the ids whose channel lists are kept (for the browser test) */
  return { updateInfo, updateChannels, close, cached: () => [...channelsKnown.keys()] };
}
