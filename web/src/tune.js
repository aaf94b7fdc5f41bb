/*
 * tune.js — the IVS tuning result (POST /v1/tune's response, paper Eqs. 11-12,
 * Figs. 26-27) as tables: the Ziegler-Nichols step-response numbers X and Y
 * and the gains K_p and T_I, then the gain schedule over mass or grade when
 * one was asked for.
 */
import { fmt } from './units.js';

/* [key in the document, label]; the rack is dimensionless, so K_p's unit is 1/(m/s) in the document */
const PARAMS = [
  ['x', 'X [s]', 'apparent dead time'],
  ['y', 'Y', 'tangent intercept (normalised)'],
  ['kp', 'K_p [rack/(m/s)]', 'proportional gain'],
  ['ti', 'T_I [s]', 'integral time'],
];
const SCHEDULE_VAR = { mass: 'mass [kg]', grade: 'grade [rad]' };

function table(className, head, rows) {
  const t = document.createElement('table');
  t.className = `results ${className}`;
  const tr = document.createElement('tr');
  for (const h of head) {
    const th = document.createElement('th');
    th.textContent = h;
    tr.append(th);
  }
  const thead = document.createElement('thead');
  thead.append(tr);
  const tbody = document.createElement('tbody');
  for (const row of rows) {
    const r = document.createElement('tr');
    for (const cell of row) {
      const td = document.createElement('td');
      if (typeof cell === 'number') {
        td.className = 'num';
        td.textContent = fmt(cell);
        td.dataset.value = String(cell);
      } else td.textContent = cell;
      r.append(td);
    }
    tbody.append(r);
  }
  t.append(thead, tbody);
  return t;
}

/** Show tuning document `doc` (api/openapi.yaml Tuning) in `root`. */
export function showTuning(root, doc) {
  const params = table(
    'tune-params',
    ['', 'value', ''],
    PARAMS.map(([k, label, what]) => [label, doc[k], what]),
  );
  PARAMS.forEach(([k], i) => (params.tBodies[0].rows[i].dataset.key = k));
  const note = document.createElement('p');
  note.className = 'hint';
  note.textContent = `plant ${doc.plant || '—'} · engine ${doc.engine_fidelity || '—'} · rack step ${fmt(doc.rack_low)} → ${fmt(doc.rack_rated)}, v ${fmt(doc.v0)} → ${fmt(doc.vb)} m/s`;
  root.replaceChildren(params, note);
  const s = doc.schedule;
  if (s && Array.isArray(s.x)) {
    const head = document.createElement('h4');
    head.textContent = `gain schedule over ${s.var}`;
    const rows = s.x.map((x, i) => [x, s.kp[i], s.ti[i]]);
    root.append(head, table('tune-schedule', [SCHEDULE_VAR[s.var] || s.var, 'K_p [rack/(m/s)]', 'T_I [s]'], rows));
  }
}
