/*
 * dom.js — `$(id)`: an element of index.html by its id. The dashboard's
 * panels are fixed in index.html; each module looks up its own elements.
 * Also the pieces the lists build their rows from: a status pill, a cell;
 * and the preset selects' options (presetOptions).
 */
export const $ = (id) => document.getElementById(id);

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

/* Fill <select> sel with one option per preset of GET /v1/presets (name, its
   description as the tooltip); unusable(p) -> a reason: the option is shown
   disabled with it. The selected name is kept when it is still listed. */
export function presetOptions(sel, presets, unusable = () => '') {
  const keep = sel.value;
  sel.replaceChildren(
    ...presets.map((p) => {
      const o = document.createElement('option');
      o.value = p.name;
      o.textContent = p.name;
      o.title = p.description || '';
      const why = unusable(p);
      if (why) {
        o.disabled = true;
        o.textContent = `${p.name} (${why})`;
      }
      return o;
    }),
  );
  if (presets.some((p) => p.name === keep)) sel.value = keep;
}
