/*
 * compare.js — overlay one channel from several sessions on one chart (e.g.
 * the same run at three track fidelities, paper Figs. 11-13). Each session's
 * series comes from GET /series, thinned with every= to about 4000 points;
 * uPlot.join aligns the different time bases into one table.
 */
import uPlot from 'uplot';
import { seriesAll } from './api.js';
import { display, fmt } from './units.js';
import { chartWidth, color } from './plots.js';

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
    for (const s of sessions) {
      const rate = s.config?.run?.sample_rate || 500;
      const count = Math.max(1, Math.round((s.t || 0) * rate));
      const every = Math.max(1, Math.ceil(count / MAX_POINTS));
      const ser = await seriesAll(s.id, { channels: channel, every });
      const ys = (ser.cols[channel] || []).map((v) => (v === null ? null : v * d.factor));
      tables.push([ser.t, ys]);
      labels.push(describe(s));
    }
    this.plot?.destroy();
    this.root.replaceChildren();
    const data = uPlot.join(tables);
    const opts = {
      title: `${channel} [${d.label}] — ${sessions.length} sessions`,
      width: chartWidth(this.root),
      height: 260,
      scales: { x: { time: false } },
      cursor: { drag: { x: true, y: false } },
      axes: [{ label: 't [s]' }, { label: d.label, size: 64, values: (u, t) => t.map((v) => fmt(v)) }],
      series: [
        { label: 't [s]', value: (u, v) => fmt(v) },
        ...labels.map((label, i) => ({ label, stroke: color(i), width: 1.5, spanGaps: true, value: (u, v) => fmt(v) })),
      ],
    };
    this.plot = new uPlot(opts, data, this.root);
    return { series: labels.length, points: data[0].length };
  }
}

/* "a1b2c3 · coupled · pointmass-prescribed" — what distinguishes sessions. */
export function describe(s) {
  const parts = [String(s.id).slice(0, 8)];
  const fid = s.config?.track?.fidelity;
  if (fid) parts.push(fid);
  if (s.preset) parts.push(s.preset);
  return parts.join(' · ');
}
