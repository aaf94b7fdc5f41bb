/*
 * compare.js — overlay one channel from several sessions on one chart (e.g.
 * the same run at three track fidelities, paper Figs. 11-13). Each session's
 * series comes from GET /series, thinned with every= to about 4000 points;
 * uPlot.join aligns the different time bases into one table. Sessions
 * without the channel (another scenario kind) are left out and named; the
 * legend lists the others in the order given (the order they were ticked),
 * each labelled with the session, the config fields that tell them apart
 * (legendFields) and the channel plotted with its display unit ("a1b2c3d4 ·
 * track/fidelity=coupled — vehicle.speed [mph]"). A field of a part of the
 * model the session does not simulate (a point mass's track, a prescribed
 * torque's engine: it has no channel of that section, SECTION_CHANNELS) is
 * not its value: the resolved config carries every section, and the legend
 * said "track/fidelity=static" for a point mass next to a coupled track
 * (review); it reads "no track".
 * The chart follows its box's width and is drawn again from the same series
 * when the channel's display unit changes (ChartPanel, plots.js).
 */
import uPlot from 'uplot';
import { seriesAll } from './api.js';
import { bracket, display, toDisplay } from './units.js';
import { ChartPanel, color, fmtValue } from './plots.js';
import { axisValues } from './ticks.js';
import { shortId } from './dom.js';

const MAX_POINTS = 4000;

export class ComparePanel extends ChartPanel {
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
    const fields = legendFields(present);
    const tables = [];
    for (const s of present) {
      const rate = s.config?.run?.sample_rate || 500;
      const count = Math.max(1, Math.round((s.t || 0) * rate));
      const every = Math.max(1, Math.ceil(count / MAX_POINTS));
      const ser = await seriesAll(s.id, { channels: channel, every });
      tables.push([ser.t, ser.cols[channel] || []]);
    }
    const labels = present.map((s) => describe(s, fields));
    this.draw({ channel, unit: ch.unit, ids: present.map((s) => s.id), labels, tables });
    return { series: labels.length, missing };
  }

  /* Draw overlay.tables ([t, SI values] per session of overlay.ids, in legend order) in the display unit of today;
     overlay.labels: each session's part of its legend entry. */
  draw(overlay) {
    const { channel, unit, tables } = overlay;
    const d = display(unit);
    const labels = overlay.labels.map((l) => `${l} — ${channel}${bracket(d.label)}`);
    const data = uPlot.join(tables.map(([t, v]) => [t, toDisplay(v, d)]));
    const opts = {
      title: `${channel}${bracket(d.label)} — ${labels.length} sessions`,
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
    this.plotted(opts, data, overlay, [unit]);
  }

  /** Whether the overlay shows session `id`. */
  shows(id) {
    return !!this.drawn?.from.ids.includes(id);
  }
}

/* The sections of the config whose fields count for a session only when it
 * simulates that part (has a channel "section.…"): the resolved config of
 * every scenario carries them all. */
const SECTION_CHANNELS = ['track', 'engine', 'control'];
const sectionOf = (k) => k.split('/')[1];
const simulates = (s, section) => (s.channels || []).some((c) => c.name.startsWith(`${section}.`));

/* The config fields of session s that describe it: {"/section/field": JSON value}, without the sections it does not simulate. */
function fieldsOf(s) {
  const flat = flatten(s.config);
  for (const k of Object.keys(flat)) if (SECTION_CHANNELS.includes(sectionOf(k)) && !simulates(s, sectionOf(k))) delete flat[k];
  return flat;
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

/* The fields that tell runs apart first, in this order (then the others alphabetically). */
const KEY_FIELDS = ['/track/fidelity', '/engine/fidelity', '/engine/variant', '/terrain/kind', '/control/mode'];
/* The legend's pseudo-field: the session's preset name. */
const PRESET = 'preset';
const MOST_FIELDS = 3;

/* Up to three fields for the legend, each one separating sessions the ones
 * before it left together (key fields first, the preset name last), until
 * every session has a label of its own or nothing separates them further. */
function legendFields(sessions) {
  const flat = sessions.map((s) => ({ ...fieldsOf(s), [PRESET]: JSON.stringify(s.preset ?? null) }));
  const others = new Set(flat.flatMap((f) => Object.keys(f)).filter((k) => k !== PRESET && !KEY_FIELDS.includes(k)));
  /* a field with one value for all never separates: the test below skips it */
  const candidates = [...KEY_FIELDS, ...[...others].sort(), PRESET];
  const groups = (fields) => new Set(flat.map((f) => JSON.stringify(fields.map((k) => f[k])))).size;
  const chosen = [];
  for (const k of candidates) {
    if (chosen.length >= MOST_FIELDS || groups(chosen) === sessions.length) break;
    if (groups([...chosen, k]) > groups(chosen)) chosen.push(k);
  }
  return chosen;
}

/* "a1b2c3d4 · track/fidelity=coupled · drive/torque=9000" — what tells the sessions apart
 * (fields: legendFields; "preset" adds the preset's name; "no track": a section it does not simulate). */
function describe(s, fields = []) {
  const parts = [shortId(s.id)];
  const flat = fieldsOf(s);
  for (const k of fields) {
    const section = sectionOf(k);
    if (k === PRESET) parts.push(s.preset || 'no preset');
    else if (SECTION_CHANNELS.includes(section) && !simulates(s, section)) {
      if (!parts.includes(`no ${section}`)) parts.push(`no ${section}`);
    }
    else parts.push(`${k.slice(1)}=${flat[k] === undefined ? '—' : flat[k].replace(/"/g, '')}`);
  }
  if (!fields.length && s.preset) parts.push(s.preset);
  return parts.join(' · ');
}
