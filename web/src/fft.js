/*
 * fft.js — amplitude spectrum of one channel over a time window, from
 * GET /v1/sessions/{id}/fft (the daemon computes it; paper Figs. 13-14 show
 * the hull's vertical-acceleration spectrum this way). Drawn with uPlot,
 * frequency in Hz on x, amplitude in the channel's display unit on y.
 * A spectrum that cannot be drawn (the daemon's error, or nothing at or
 * below "show up to") throws; the caller clears the old one and says why.
 * The chart follows its box's width and is drawn again from the same
 * document when the channel's display unit changes (ChartPanel, plots.js).
 */
import { api, ApiError } from './api.js';
import { bracket, display, fmt, toDisplay } from './units.js';
import { ChartPanel, fmtValue } from './plots.js';
import { axisValues } from './ticks.js';

export class FftPanel extends ChartPanel {
  /* fmax: highest frequency shown [Hz] (0/undefined: all); log: logarithmic
   * amplitude axis. */
  async compute(session, channel, from, to, { fmax, log } = {}) {
    const ch = (session.channels || []).find((c) => c.name === channel) || { unit: '' };
    const doc = await api.fft(session.id, { channel, from, to });
    this.draw({ doc, channel, unit: doc.unit || ch.unit, from, to, fmax, log });
  }

  /* Draw spec.doc (api/openapi.yaml Spectrum) of spec.channel (SI spec.unit) in the display unit of today. */
  draw(spec) {
    const { doc, channel, unit, from, to, fmax, log } = spec;
    const freq = doc.frequency || [];
    const d = display(unit);
    /* Leave out the DC bin: the mean dwarfs the vibration content. */
    let xs = freq.slice(1);
    let yy = toDisplay((doc.amplitude || []).slice(1), d);
    if (log) yy = yy.map((v) => (v > 0 ? v : null));
    if (!xs.length) throw new ApiError(0, { title: 'No spectrum', detail: `the window ${fmt(doc.from)}–${fmt(doc.to)} s holds ${doc.n} samples: widen it` });
    if (fmax > 0) {
      const n = xs.findIndex((f) => f > fmax);
      if (n === 0)
        throw new ApiError(0, {
          title: 'Nothing to show',
          detail: `show up to ${fmt(fmax)} Hz is below the first frequency bin, ${fmt(xs[0])} Hz (df = 1 / window length): raise it or widen the time window`,
        });
      if (n > 0) {
        xs = xs.slice(0, n);
        yy = yy.slice(0, n);
      }
    }
    const opts = {
      title: `Amplitude spectrum of ${channel} (${fmt(doc.from ?? from ?? 0)}–${fmt(doc.to ?? to ?? 0)} s, ${freq.length} bins)`,
      height: 220,
      scales: { x: { time: false }, y: log ? { distr: 3 } : {} },
      cursor: { drag: { x: true, y: false } },
      axes: [
        { label: 'frequency [Hz]', values: axisValues },
        { label: `amplitude${bracket(d.label)}`, size: 64, values: axisValues },
      ],
      series: [
        { label: 'f [Hz]', value: fmtValue },
        { label: `|${channel}|${bracket(d.label)}`, stroke: '#7c3aed', width: 1.5, fill: 'rgba(124,58,237,0.08)', value: fmtValue },
      ],
    };
    this.plotted(opts, [xs, yy], spec, [unit]);
  }
}
