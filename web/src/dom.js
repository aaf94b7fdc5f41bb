/*
 * dom.js — `$(id)`: an element of index.html by its id. The dashboard's
 * panels are fixed in index.html; each module looks up its own elements.
 * Also the pieces the lists build their rows from: a status pill, a cell.
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
