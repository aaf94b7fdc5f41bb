/*
 * compare.js — overlay one channel from several sessions on one chart (e.g.
 * the same run at three track fidelities, paper Figs. 11-13). Each session's
 * series comes from GET /series, thinned with every= to about 4000 points;
 * uPlot.join aligns the different time bases into one table.
 */
import uPlot from 'uplot';
import { seriesAll } from './api.js';
import { bracket, display, toDisplay } from './units.js';
import { chartWidth, color, fmtTicks, fmtValue } from './plots.js';

const MAX_POINTS = 4000;

export class ComparePanel {
  constructor(root) {
    this.root = root;
    this.plot = null;
  }

  /** sessions: full session objects (with channels, t, config). */
  async show(sessions, channel) {
    const ch = sessions.flatMap((s) => s.channels || []).find((c) => c.name === channel) || { unit: '' };
    const d = display(ch.unit);
    const tables = [];
    const labels = [];
    const differing = differingFields(sessions);
    for (const s of sessions) {
      const rate = s.config?.run?.sample_rate || 500;
      const count = Math.max(1, Math.round((s.t || 0) * rate));
      const every = Math.max(1, Math.ceil(count / MAX_POINTS));
      const ser = await seriesAll(s.id, { channels: channel, every });
      tables.push([ser.t, toDisplay(ser.cols[channel] || [], d)]);
      labels.push(describe(s, differing));
    }
    this.plot?.destroy();
    this.root.replaceChildren();
    const data = uPlot.join(tables);
    const opts = {
      title: `${channel}${bracket(d.label)} — ${sessions.length} sessions`,
      width: chartWidth(this.root),
      height: 260,
      scales: { x: { time: false } },
      cursor: { drag: { x: true, y: false } },
      axes: [{ label: 't [s]' }, { label: d.label || channel, size: 64, values: fmtTicks }],
      series: [
        { label: 't [s]', value: fmtValue },
        ...labels.map((label, i) => ({ label, stroke: color(i), width: 1.5, spanGaps: true, value: fmtValue })),
      ],
    };
    this.plot = new uPlot(opts, data, this.root);
    return { series: labels.length, points: data[0].length };
  }
}

/* Flatten a config document to {"/section/field": value}. */
function flatten(doc, prefix = '', out = {}) {
  for (const [k, v] of Object.entries(doc || {})) {
    if (k.startsWith('_') || k === 'description') continue;
    if (v && typeof v === 'object' && !Array.isArray(v)) flatten(v, `${prefix}/${k}`, out);
    else out[`${prefix}/${k}`] = JSON.stringify(v);
  }
  return out;
}

/* JSON Pointers whose values differ between the sessions' resolved configs. */
export function differingFields(sessions) {
  const flat = sessions.map((s) => flatten(s.config));
  const keys = new Set(flat.flatMap((f) => Object.keys(f)));
  return [...keys].filter((k) => new Set(flat.map((f) => f[k])).size > 1).sort();
}

/* "a1b2c3d4 · track/fidelity=coupled · drive/torque=9000" — what tells the sessions apart. */
export function describe(s, differing = []) {
  const parts = [String(s.id).slice(0, 8)];
  const flat = flatten(s.config);
  for (const k of differing.slice(0, 3)) parts.push(`${k.slice(1)}=${flat[k] === undefined ? '—' : flat[k].replace(/"/g, '')}`);
  if (!differing.length && s.preset) parts.push(s.preset);
  return parts.join(' · ');
}
