/*
 * compare_controls.js — the Compare panel's controls: the sessions ticked in
 * the list (state.compare), the channel to overlay, and the Compare button
 * that draws them with ComparePanel (compare.js).
 */
import { api, ApiError } from './api.js';
import { $ } from './dom.js';
import { hideError, showError } from './messages.js';
import { channelsOf, fillChannelSelect } from './channels.js';

export function initCompareControls(state, compare) {
  function updateInfo() {
    const n = state.compare.size;
    $('compare-info').textContent = n ? `${n} session${n > 1 ? 's' : ''} ticked` : 'none ticked';
  }

  async function onCompare() {
    const box = $('compare-error');
    hideError(box);
    if (state.compare.size < 1) {
      showError(box, new ApiError(0, { title: 'Nothing to compare', detail: 'tick sessions in the list (cmp column) first' }));
      return;
    }
    try {
      const sessions = await Promise.all([...state.compare].map((id) => api.session(id)));
      const chans = [];
      for (const s of sessions) for (const c of channelsOf(s)) if (!chans.some((x) => x.name === c.name)) chans.push(c);
      const sel = $('compare-channel');
      if (!chans.some((c) => c.name === sel.value)) fillChannelSelect(sel, chans, state.picks[0]);
      const r = await compare.show(sessions, sel.value);
      const lacking = r.missing.map((s) => String(s.id).slice(0, 8)).join(', ');
      $('compare-info').textContent = `${r.series} session${r.series > 1 ? 's' : ''} overlaid${lacking ? ` · not plotted, no channel ${sel.value}: ${lacking}` : ''}`;
    } catch (e) {
      compare.clear(); /* an overlay of an earlier request would pass for this one */
      showError(box, e);
    }
  }

  /* The channel list, filled from the open session until a comparison fills it. */
  function updateChannels() {
    if ($('compare-channel').options.length) return;
    const chans = state.session ? channelsOf(state.session) : [];
    fillChannelSelect($('compare-channel'), chans, state.picks[0]);
  }

  /* Session `id` was closed: an overlay that shows it goes. */
  function close(id) {
    if (compare.shows(id)) compare.clear();
  }

  $('compare-btn').addEventListener('click', onCompare);
  $('compare-channel').addEventListener('focus', updateChannels);
  updateInfo();

  return { updateInfo, updateChannels, close };
}
