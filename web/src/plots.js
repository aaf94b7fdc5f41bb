/*
 * plots.js — live time-series charts (uPlot) for the chosen channels of one
 * session, with synchronized cursors, drag-to-zoom (double-click resets) and
 * display-unit conversion (SI in the data; mph / rpm only on screen). Also
 * what every chart shares: its width (followWidth: the box's, when the window
 * or the layout changes), colours and legend values, and ChartPanel, the base
 * of the one-chart panels (fft.js, compare.js, engine_map.js).
 * The live charts' redraw cadence follows what a redraw costs (see LivePlots).
 */
import uPlot from 'uplot';
import { bracket, display, extendDisplay, fmt, UNITS_CHANGED } from './units.js';
import { axisValues } from './ticks.js';

/* Channels picked by default when a session opens: the paper's plotted
 * quantities (vehicle speed, engine speed, gear, rack, sprocket torque, rear
 * roller track tension, roller normal force, hull acceleration), matched by
 * name so any scenario's equivalents are found. */
const DEFAULT_PICKS = [
  [/^vehicle\.speed$/],
  [/^engine\.speed$/],
  [/gear$/, /gear/],
  [/(^|[._])rack($|[._])/], /* not the 'rack' inside 'track' */
  [/^sprocket\.torque$/],
  [/^track\.tension\.rear_roller$/, /tension.*rear|rear.*tension/],
  [/^roller\.rear\.normal_force$/, /roller.*normal|normal.*roller/],
  [/^hull\.accel_z$/, /hull.*acc/, /^vehicle\.accel$/],
];

/** Names of the channels to show first: per entry the first alternative present. */
export function defaultPicks(channels) {
  const names = channels.map((c) => c.name);
  const picked = [];
  for (const alts of DEFAULT_PICKS) {
    for (const re of alts) {
      const n = names.find((x) => re.test(x) && !picked.includes(x));
      if (n) {
        picked.push(n);
        break;
      }
    }
  }
  return picked.length ? picked : names.slice(0, 4);
}

const COLORS = ['#2563eb', '#dc2626', '#059669', '#d97706', '#7c3aed', '#0891b2', '#db2777', '#4b5563'];
export const color = (i) => COLORS[i % COLORS.length];

/* uPlot legend values shared by every chart (axis ticks: ticks.js). */
export const fmtValue = (u, v) => fmt(v);

function chartWidth(container) {
  return Math.max(280, Math.floor(container.getBoundingClientRect().width) - 4);
}

/* Keep the uPlots in `root` (plots(): the current ones) as wide as root, each
 * at its own height, when the window or the layout changes. */
function followWidth(root, plots) {
  new ResizeObserver(() => {
    const w = chartWidth(root);
    for (const p of plots()) if (Math.abs(p.width - w) > 2) p.setSize({ width: w, height: p.height });
  }).observe(root);
}

/* A panel of one chart drawn from one answer (a spectrum, an overlay, an
 * engine map): this.plot, a uPlot in this.root, follows the box's width.
 * A subclass's draw(from) builds the chart from `from` in today's display
 * units and hands it to plotted(); when the display unit of a quantity the
 * chart shows changes (units.js UNITS_CHANGED, detail.siUnit), draw(from)
 * runs again (other changes leave the chart, and its zoom, alone). clear()
 * takes the chart and what it was drawn from away. */
export class ChartPanel {
  constructor(root) {
    this.root = root;
    this.plot = null;
    this.drawn = null; /* {from, units}: what the chart was drawn from, and the SI units of what it shows */
    followWidth(root, () => (this.plot ? [this.plot] : []));
    window.addEventListener(UNITS_CHANGED, ({ detail }) => {
      if (this.drawn && this.drawn.units.includes(detail.siUnit)) this.draw(this.drawn.from);
    });
  }

  /* The chart becomes uPlot(opts, data), drawn from `from`; units: the SI units of the quantities it shows. */
  plotted(opts, data, from, units) {
    this.plot?.destroy();
    this.root.replaceChildren();
    this.plot = new uPlot({ width: chartWidth(this.root), ...opts }, data, this.root);
    this.drawn = { from, units };
  }

  clear() {
    this.plot?.destroy();
    this.plot = null;
    this.drawn = null;
    this.root.replaceChildren();
  }
}

/* The live charts' cadence: every TICK_MS a tick draws the rows the store
 * gained, but drawing may take at most DRAW_SHARE of wall time: a redraw
 * that cost c ms (smoothed over the last ones) lets the next one start
 * c / DRAW_SHARE ms after it at the earliest, and the ticks in between are
 * skipped. Nothing is lost: a later tick draws everything the store holds,
 * so its last state is drawn at most that long after it came. (36 charts of
 * 40,000 rows cost ~22 ms a redraw in headless chromium: one every 500-750 ms.) */
const TICK_MS = 250;
const DRAW_SHARE = 0.05;
const SMOOTH = 0.3; /* weight of the latest redraw in the smoothed cost */

/* The rows of `store` as a redraw finds them: {store, rows, lastIndex, t} (t: the last row's). */
export function rowsOf(store) {
  const rows = store?.length || 0;
  return { store, rows, lastIndex: store?.lastIndex ?? rows - 1, t: rows ? store.t[rows - 1] : undefined };
}

/* onDraw(drawnRows) hears of every redraw, right after it: the labels that
 * tell how far the data goes (sample count, run progress) are written from
 * the rows drawn, so they never show less than the charts (they lagged up to
 * 300 ms, a second of a 5x run, behind: review). */
export class LivePlots {
  constructor(root, { onDraw = () => {} } = {}) {
    this.root = root;
    this.onDraw = onDraw;
    this.drawnRows = null; /* rowsOf(the store) at the last redraw */
    this.charts = []; /* {name, unit, d, plot, zoomed, el, col, shown}: shown, the store's column col in display unit d */
    this.store = null;
    this.drawnVersion = -1;
    this.timer = null;
    this.cost = 0; /* [ms] a tick's redraw of the charts shown, smoothed (0: none measured yet) */
    this.lastDraw = -Infinity; /* [ms, performance.now()] when the last redraw began */
    followWidth(root, () => this.charts.map((c) => c.plot));
  }

  /** Show the channels `names` of `store`. Drawn again for the same store (a
   * unit change, another channel picked), a zoomed chart keeps its x range. */
  show(store, names) {
    const zooms = store === this.store ? Object.fromEntries(this.charts.filter((c) => c.zoomed).map((c) => [c.name, { min: c.plot.scales.x.min, max: c.plot.scales.x.max }])) : {};
    this.destroyCharts();
    this.store = store;
    this.drawnVersion = -1;
    this.cost = 0; /* other charts: measured anew, from the first tick's redraw */
    names.forEach((name, i) => {
      const ch = store.channels.find((c) => c.name === name);
      if (ch) this.charts.push(this.makeChart(ch, color(i)));
    });
    for (const c of this.charts) c.zoomed = !!zooms[c.name]; /* redraw leaves their x scale alone */
    this.redraw(true);
    for (const c of this.charts) if (zooms[c.name]) c.plot.setScale('x', zooms[c.name]);
    if (!this.timer) this.timer = setInterval(() => this.redraw(false), TICK_MS);
  }

  makeChart(ch, stroke) {
    const d = display(ch.unit);
    const box = document.createElement('div');
    box.className = 'chart';
    box.dataset.channel = ch.name;
    this.root.append(box);
    const entry = { name: ch.name, unit: ch.unit, d, zoomed: false, el: box, col: null, shown: [] };
    const opts = {
      title: `${ch.name}${bracket(d.label)}${ch.description ? ' — ' + ch.description : ''}`,
      width: chartWidth(this.root),
      height: 190,
      cursor: { sync: { key: 'tanksim-live' }, drag: { x: true, y: false } },
      scales: { x: { time: false } },
      legend: { live: true },
      axes: [
        { label: 't [s]', size: 36, values: axisValues },
        { label: d.label || ch.name, size: 64, values: axisValues },
      ],
      series: [
        { label: 't [s]', value: fmtValue },
        { label: `${ch.name}${bracket(d.label)}`, stroke, width: 1.5, value: fmtValue },
      ],
      hooks: {
        /* zoomed = the x range is narrower than the data: then new data must
         * not reset the user's zoom. */
        setScale: [
          (u, key) => {
            if (key !== 'x') return;
            const xs = u.data[0];
            if (!xs || xs.length < 2) return;
            const eps = 1e-9 * Math.max(1, Math.abs(xs[xs.length - 1]));
            entry.zoomed = u.scales.x.min > xs[0] + eps || u.scales.x.max < xs[xs.length - 1] - eps;
          },
        ],
      },
    };
    entry.plot = new uPlot(opts, [[], []], box);
    entry.plot.over.addEventListener('dblclick', () => {
      entry.zoomed = false;
      this.redraw(true);
    });
    return entry;
  }

  /* [t, the channel in the chart's display unit]. Each redraw converts only
   * the rows the store gained since the last (entry.shown grows with the
   * column); a unit or channel change makes new charts (show), converted
   * from the first row. */
  data(entry) {
    const col = this.store.cols[entry.name] || [];
    if (entry.d.factor === 1) return [this.store.t, col];
    if (entry.col !== col) Object.assign(entry, { col, shown: [] }); /* the first redraw, or a column the store replaced: from the start */
    return [this.store.t, extendDisplay(entry.shown, col, entry.d)];
  }

  /* Draw what the store holds: at once when forced (new charts, a zoom reset),
   * else when it changed and the cadence allows (DRAW_SHARE; a skipped tick
   * leaves the rows for the next). */
  redraw(force) {
    if (!this.store || (!force && this.store.version === this.drawnVersion)) return;
    const t0 = performance.now();
    if (!force && t0 - this.lastDraw < this.cost / DRAW_SHARE) return;
    this.drawnVersion = this.store.version;
    for (const c of this.charts) {
      if (c.zoomed) c.plot.setData(this.data(c), false); /* the user's x range: uPlot draws nothing */
      else c.plot.batch(() => c.plot.setData(this.data(c))); /* drawn now, not in a microtask: the cost measured is the drawing's */
    }
    const ms = performance.now() - t0;
    this.lastDraw = t0;
    /* new charts' first draw costs more (layout): not what a tick costs */
    if (!force) this.cost = this.cost ? (1 - SMOOTH) * this.cost + SMOOTH * ms : ms;
    this.drawnRows = rowsOf(this.store);
    this.onDraw(this.drawnRows);
  }

  destroyCharts() {
    for (const c of this.charts) {
      c.plot.destroy();
      c.el.remove();
    }
    this.charts = [];
  }

  stop() {
    clearInterval(this.timer);
    this.timer = null;
    this.destroyCharts();
    this.store = null;
    this.drawnRows = null;
  }
}
