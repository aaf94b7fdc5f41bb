/*
 * engine_map.js — the engine's full-load map (POST /v1/engine-map's response,
 * paper Fig. 18) drawn with uPlot: brake torque (left axis) and power (right
 * axis) over engine speed in rpm, one point per speed, and the one-line
 * summary of the rated point. Columns are found by name in the map's column
 * table (name, unit); values are converted for display only (units.js),
 * drawn again from the same map when the display unit of a column it plots
 * changes. The chart follows its box's width (ChartPanel, plots.js).
 */
import { ApiError } from './api.js';
import { bracket, display, fmt, toDisplay } from './units.js';
import { ChartPanel, color, fmtValue } from './plots.js';
import { axisValues } from './ticks.js';

export class EngineMapPanel extends ChartPanel {
  /* root: the chart's container; summary: the element of the rated-point line */
  constructor(root, summary) {
    super(root);
    this.summary = summary;
  }

  /** Draw map document `doc` (api/openapi.yaml EngineMap); throws when it lacks a column. */
  draw(doc) {
    const cols = doc.columns || [];
    const find = (name) => {
      const i = cols.findIndex((c) => c.name === name);
      if (i < 0) throw new ApiError(0, { title: 'Unexpected engine map', detail: `no column ${name} in the daemon's answer` });
      return { i, unit: cols[i].unit, d: display(cols[i].unit) };
    };
    const speed = find('speed_rpm');
    const torque = find('torque');
    const power = find('power');
    const rows = doc.rows || [];
    const column = ({ i, d }) => toDisplay(rows.map((r) => r[i]), d);
    const tLabel = `brake torque${bracket(torque.d.label)}`;
    const pLabel = `power${bracket(power.d.label)}`;
    const opts = {
      title: `Full-load map: ${doc.variant}, ${doc.fidelity}, rack ${fmt(doc.rack)}`,
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
    this.plotted(opts, [column(speed), column(torque), column(power)], doc, [speed.unit, torque.unit, power.unit]);
    const r = doc.rated || {};
    /* the power in the unit its axis shows (W toggle); the hp beside it and
       the speed in rpm, as the map's columns give them */
    const pd = display('W');
    this.summary.textContent = `rated: ${fmt(r.power_w * pd.factor)} ${pd.label} (${fmt(r.power_hp)} hp) at ${fmt(r.speed_rpm)} rpm`;
    this.summary.dataset.powerKw = String(r.power_w / 1000);
  }

  clear() {
    super.clear();
    this.summary.textContent = '';
    delete this.summary.dataset.powerKw;
  }
}
