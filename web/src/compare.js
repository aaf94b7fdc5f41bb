/*
 * compare.js — overlay one channel from several sessions on one chart (e.g.
 * the same run at three track fidelities, paper Figs. 11-13). Each session's
 * series comes from GET /series, thinned with every= to about 4000 points;
 * uPlot.join aligns the different time bases into one table. Sessions
 * without the channel (another scenario kind) are left out and named; the
 * legend lists the others in the order given (the order they were ticked).
 */
import uPlot from 'uplot';
import { seriesAll } from './api.js';
import { bracket, display, toDisplay } from './units.js';
import { chartWidth, color, fmtValue } from './plots.js';
import { axisValues } from './ticks.js';
import { shortId } from './dom.js';

const MAX_POINTS = 4000;

export class ComparePanel {
  constructor(root) {
    this.root = root;
    this.plot = null;
    this.ids = []; /* sessions overlaid, in legend order */
  }

  /**
   * sessions: full session objects (with channels, t, config), in legend order.
   * Returns {series, missing: [sessions without the channel]};
   * throws when none has it.
   */
  async show(sessions, channel) {
    const has = (s) => (s.channels || []).some((c) => c.name === channel);
    const present = sessions.filter(has);
    const missing = sessions.filter((s) => !has(s));
    if (!present.length) throw new Error(`none of the ticked sessions has the channel ${channel}`);
    const ch = present[0].channels.find((c) => c.name === channel);
    const d = display(ch.unit);
    const differing = differingFields(present);
    const tables = [];
    for (const s of present) {
      const rate = s.config?.run?.sample_rate || 500;
      const count = Math.max(1, Math.round((s.t || 0) * rate));
      const every = Math.max(1, Math.ceil(count / MAX_POINTS));
      const ser = await seriesAll(s.id, { channels: channel, every });
      tables.push([ser.t, toDisplay(ser.cols[channel] || [], d)]);
    }
    const labels = present.map((s) => describe(s, differing));
    this.clear();
    const data = uPlot.join(tables);
    const opts = {
      title: `${channel}${bracket(d.label)} — ${present.length} sessions`,
      width: chartWidth(this.root),
      height: 260,
      scales: { x: { time: false } },
      cursor: { drag: { x: true, y: false } },
      axes: [
        { label: 't [s]', values: axisValues },
        { label: d.label || channel, size: 64, values: axisValues },
      ],
      series: [
        { label: 't [s]', value: fmtValue },
        ...labels.map((label, i) => ({ label, stroke: color(i), width: 1.5, spanGaps: true, value: fmtValue })),
      ],
    };
    this.plot = new uPlot(opts, data, this.root);
    this.ids = present.map((s) => s.id);
    return { series: labels.length, missing };
  }

  /** Whether the overlay shows session `id`. */
  shows(id) {
    return this.ids.includes(id);
  }

  clear() {
    this.plot?.destroy();
    this.plot = null;
    this.ids = [];
    this.root.replaceChildren();
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
  const parts = [shortId(s.id)];
  const flat = flatten(s.config);
  for (const k of differing.slice(0, 3)) parts.push(`${k.slice(1)}=${flat[k] === undefined ? '—' : flat[k].replace(/"/g, '')}`);
  if (!differing.length && s.preset) parts.push(s.preset);
  return parts.join(' · ');
}
