/*
 * fft.js — amplitude spectrum of one channel over a time window, from
 * GET /v1/sessions/{id}/fft (the daemon computes it; paper Figs. 13-14 show
 * the hull's vertical-acceleration spectrum this way). Drawn with uPlot,
 * frequency in Hz on x, amplitude in the channel's display unit on y.
 */
import uPlot from 'uplot';
import { api } from './api.js';
import { bracket, display, fmt, toDisplay } from './units.js';
import { chartWidth, fmtTicks, fmtValue } from './plots.js';

export class FftPanel {
  constructor(root) {
    this.root = root;
    this.plot = null;
  }

  /* fmax: highest frequency shown [Hz] (the whole spectrum is kept: zoom out
   * with a double-click); log: logarithmic amplitude axis. */
  async compute(session, channel, from, to, { fmax, log } = {}) {
    const ch = (session.channels || []).find((c) => c.name === channel) || { unit: '' };
    const doc = await api.fft(session.id, { channel, from, to });
    const freq = doc.frequency || []; /* api/openapi.yaml Spectrum */
    const d = display(doc.unit || ch.unit);
    /* Leave out the DC bin: the mean dwarfs the vibration content. */
    let xs = freq.slice(1);
    let yy = toDisplay((doc.amplitude || []).slice(1), d);
    if (log) yy = yy.map((v) => (v > 0 ? v : null));
    if (fmax > 0) {
      const n = xs.findIndex((f) => f > fmax);
      if (n > 1) {
        xs = xs.slice(0, n);
        yy = yy.slice(0, n);
      }
    }
    this.plot?.destroy();
    this.root.replaceChildren();
    const opts = {
      title: `Amplitude spectrum of ${channel} (${fmt(doc.from ?? from ?? 0)}–${fmt(doc.to ?? to ?? 0)} s, ${freq.length} bins)`,
      width: chartWidth(this.root),
      height: 220,
      scales: { x: { time: false }, y: log ? { distr: 3 } : {} },
      cursor: { drag: { x: true, y: false } },
      axes: [{ label: 'frequency [Hz]' }, { label: `amplitude${bracket(d.label)}`, size: 64, values: fmtTicks }],
      series: [
        { label: 'f [Hz]', value: fmtValue },
        { label: `|${channel}|${bracket(d.label)}`, stroke: '#7c3aed', width: 1.5, fill: 'rgba(124,58,237,0.08)', value: fmtValue },
      ],
    };
    this.plot = new uPlot(opts, [xs, yy], this.root);
    return { bins: xs.length };
  }

  clear() {
    this.plot?.destroy();
    this.plot = null;
    this.root.replaceChildren();
  }
}
