/*
 * dom.js — `$(id)`: an element of index.html by its id. The dashboard's
 * panels are fixed in index.html; each module looks up its own elements.
 * Also the pieces the lists build their rows from: a status pill, a cell;
 * the preset selects' options (presetOptions); and a progress bar's value
 * (setBar).
 */
export const $ = (id) => document.getElementById(id);

/* The first 8 characters of a session id: how the page names a session. */
export const shortId = (id) => String(id).slice(0, 8);

/* <span class="pill st-STATUS">STATUS</span> (style.css colours it by status). */
export function pill(status) {
  const e = document.createElement('span');
  e.className = `pill st-${status || 'unknown'}`;
  e.textContent = status || '?';
  return e;
}

/* <td class=className>content</td> */
export function cell(content, className) {
  const td = document.createElement('td');
  if (className) td.className = className;
  td.append(content);
  return td;
}

/* Fill <select> sel with one <option> per item, toOption(item) giving its
   fields ({value, text, title, disabled, data}); the value keep (by default
   the current one) stays selected when it is still listed. */
export function fillSelect(sel, items, toOption, keep = sel.value) {
  sel.replaceChildren(
    ...items.map((item) => {
      const { value, text, title = '', disabled = false, data = {} } = toOption(item);
      const o = document.createElement('option');
      Object.assign(o, { value, textContent: text, title, disabled });
      Object.assign(o.dataset, data);
      return o;
    }),
  );
  if ([...sel.options].some((o) => o.value === keep)) sel.value = keep;
}

/* Fill <select> sel with the presets of GET /v1/presets (name, its description
   as the tooltip); unusable(p) -> a reason: the option is shown disabled with it. */
export function presetOptions(sel, presets, unusable = () => '') {
  fillSelect(sel, presets, (p) => {
    const why = unusable(p);
    return { value: p.name, text: why ? `${p.name} (${why})` : p.name, title: p.description || '', disabled: Boolean(why) };
  });
}

/* Select `value` in `sel` when it is one of its options (true); else leave it (false). */
export function selectIf(sel, value) {
  if (typeof value !== 'string' || ![...sel.options].some((o) => o.value === value)) return false;
  sel.value = value;
  return true;
}

/* Progress bar `el` (role=progressbar, its .bar inside) at `pct` % shown with
   `digits` decimals: the bar's width, data-percent and aria-valuenow; pct
   null: empty, with no data-percent. */
export function setBar(el, pct, digits = 0) {
  const v = pct === null ? '0' : pct.toFixed(digits);
  el.querySelector('.bar').style.width = `${v}%`;
  if (pct === null) delete el.dataset.percent;
  else el.dataset.percent = v;
  el.setAttribute('aria-valuenow', v);
}
