/*
 * engine_map.js — the engine's full-load map (POST /v1/engine-map's response,
 * paper Fig. 18) drawn with uPlot: brake torque (left axis) and power (right
 * axis) over engine speed in rpm, one point per speed, and the one-line
 * summary of the rated point. Columns are found by name in the map's column
 * table (name, unit); values are converted for display only (units.js),
 * drawn again from the same map when a display unit changes. The chart
 * follows its box's width.
 */
import uPlot from 'uplot';
import { ApiError } from './api.js';
import { bracket, display, fmt, toDisplay, UNITS_CHANGED } from './units.js';
import { chartWidth, color, fmtValue, followSize } from './plots.js';
import { axisValues } from './ticks.js';

export class EngineMapPanel {
  /* root: the chart's container; summary: the element of the rated-point line */
  constructor(root, summary) {
    this.root = root;
    this.summary = summary;
    this.plot = null;
    this.doc = null; /* the map drawn */
    followSize(this, 240);
    window.addEventListener(UNITS_CHANGED, () => this.doc && this.show(this.doc)); /* torque and power axes' units */
  }

  /** Draw map document `doc` (api/openapi.yaml EngineMap); throws when it lacks a column. */
  show(doc) {
    const cols = doc.columns || [];
    const find = (name) => {
      const i = cols.findIndex((c) => c.name === name);
      if (i < 0) throw new ApiError(0, { title: 'Unexpected engine map', detail: `no column ${name} in the daemon's answer` });
      return { i, d: display(cols[i].unit) };
    };
    const speed = find('speed_rpm');
    const torque = find('torque');
    const power = find('power');
    const rows = doc.rows || [];
    const column = ({ i, d }) => toDisplay(rows.map((r) => r[i]), d);
    const tLabel = `brake torque${bracket(torque.d.label)}`;
    const pLabel = `power${bracket(power.d.label)}`;
    this.clear();
    const opts = {
      title: `Full-load map: ${doc.variant}, ${doc.fidelity}, rack ${fmt(doc.rack)}`,
      width: chartWidth(this.root),
      height: 240,
      scales: { x: { time: false }, torque: {}, power: {} },
      cursor: { drag: { x: true, y: false } },
      axes: [
        { label: 'speed [rpm]', values: axisValues },
        { scale: 'torque', label: tLabel, size: 64, values: axisValues, stroke: color(0) },
        { scale: 'power', label: pLabel, side: 1, size: 64, values: axisValues, stroke: color(1), grid: { show: false } },
      ],
      series: [
        { label: 'speed [rpm]', value: fmtValue },
        { label: tLabel, scale: 'torque', stroke: color(0), width: 1.5, points: { show: true }, value: fmtValue },
        { label: pLabel, scale: 'power', stroke: color(1), width: 1.5, points: { show: true }, value: fmtValue },
      ],
    };
    this.plot = new uPlot(opts, [column(speed), column(torque), column(power)], this.root);
    const r = doc.rated || {};
    this.summary.textContent = `rated: ${fmt(r.power_w / 1000)} kW (${fmt(r.power_hp)} hp) at ${fmt(r.speed_rpm)} rpm`;
    this.summary.dataset.powerKw = String(r.power_w / 1000);
    this.doc = doc;
  }

  clear() {
    this.plot?.destroy();
    this.plot = null;
    this.doc = null;
    this.root.replaceChildren();
    this.summary.textContent = '';
    delete this.summary.dataset.powerKw;
  }
}
