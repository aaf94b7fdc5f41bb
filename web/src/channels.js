/*
 * channels.js — the open session's channels: the chips that pick what is
 * charted, the unit toggles (mph / m/s / km/h, ...), and the channel
 * <select>s of the FFT and Compare panels, each labelled with the unit the
 * charts draw it in.
 */
import { $, fillSelect } from './dom.js';
import { bracket, choices, display, setDisplay, UNITS_CHANGED } from './units.js';

/* A session's channels less the time axis. */
export function channelsOf(s) {
  return (s.channels || []).filter((c) => c.name !== 't');
}

/* Options "name [display unit]": the unit the charts draw the channel in; `selected` (by default the current one) stays chosen while listed (fillSelect). */
export function fillChannelSelect(sel, chans, selected) {
  fillSelect(sel, chans, (c) => ({ value: c.name, text: `${c.name}${bracket(display(c.unit).label)}`, data: { unit: c.unit } }), selected);
}

/* The channels a select lists, as it was filled. */
const listed = (sel) => [...sel.options].map((o) => ({ name: o.value, unit: o.dataset.unit }));

/* The chips and toggles of the open session; picking a chip sets state.picks and redraws the charts. */
export function initChannelPicker(state, plots) {
  function renderChannelPicker() {
    const box = $('channel-list');
    box.replaceChildren();
    for (const c of channelsOf(state.session)) {
      const lab = document.createElement('label');
      lab.className = 'chip';
      lab.title = c.description || '';
      const cb = document.createElement('input');
      cb.type = 'checkbox';
      cb.value = c.name;
      cb.checked = state.picks.includes(c.name);
      cb.addEventListener('change', () => {
        state.picks = [...box.querySelectorAll('input:checked')].map((x) => x.value);
        plots.show(state.store, state.picks);
      });
      lab.append(cb, ` ${c.name} `);
      const u = document.createElement('span');
      u.className = 'unit';
      u.textContent = bracket(display(c.unit).label);
      lab.append(u);
      box.append(lab);
    }
  }

  function renderUnitToggles() {
    const box = $('unit-toggles');
    box.replaceChildren();
    const units = [...new Set(channelsOf(state.session).map((c) => c.unit))];
    for (const u of units) {
      const list = choices(u);
      if (list.length < 2) continue;
      const group = document.createElement('span');
      group.className = 'seg';
      group.dataset.unit = u;
      const cap = document.createElement('span');
      cap.className = 'muted';
      cap.textContent = { 'm/s': 'speed', 'rad/s': 'rotation', rad: 'angle', W: 'power', Pa: 'pressure' }[u] || u;
      group.append(cap);
      group.setAttribute('role', 'group');
      group.setAttribute('aria-label', `${cap.textContent} unit`);
      for (const c of list) {
        const b = document.createElement('button');
        const on = display(u).label === c.label;
        b.type = 'button';
        b.className = `small seg-btn${on ? ' on' : ''}`;
        b.setAttribute('aria-pressed', on ? 'true' : 'false'); /* the chosen unit, for assistive technology too */
        b.textContent = c.label;
        b.addEventListener('click', () => setDisplay(u, c.label));
        group.append(b);
      }
      box.append(group);
    }
  }

  function render() {
    renderChannelPicker();
    renderUnitToggles();
  }

  function clear() {
    $('channel-list').replaceChildren();
    $('unit-toggles').replaceChildren();
  }

  /* every display-unit change (units.js), whichever control made it; the
   * live charts are rebuilt only when one of them shows that quantity */
  window.addEventListener(UNITS_CHANGED, ({ detail }) => {
    if (!state.session) return;
    render();
    for (const sel of [$('fft-channel'), $('compare-channel')]) fillChannelSelect(sel, listed(sel)); /* new unit labels */
    if (plots.charts.some((c) => c.unit === detail.siUnit)) plots.show(state.store, state.picks);
  });

  return { render, clear };
}
