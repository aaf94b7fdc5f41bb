/*
 * ticks.js — axis tick labels: one number format per axis.
 *
 * uPlot hands an axis's values() its tick values, null for the ticks it
 * leaves unlabelled (on a log axis, those between 1, 2 and 5 of a decade).
 * All labelled ticks of an axis get the same format: fixed-point with the
 * decimals the finest tick needs ("0.0 0.5 1.0 1.5"), or, when a tick is
 * very large or very small or the ticks span many decades (log axes),
 * exponential with one mantissa precision ("1e-4 1e-3 1e-2", "5.0e-4 1.0e-3").
 */

const MAX_DIGITS = 6;
const exact = (v, s) => Math.abs(Number(s) - v) <= 1e-9 * Math.max(Math.abs(v), 1e-300);

/* Fewest digits d (0..MAX_DIGITS) for which format(v, d) is exact for every v. */
function digits(values, format) {
  for (let d = 0; d < MAX_DIGITS; d++) if (values.every((v) => exact(v, format(v, d)))) return d;
  return MAX_DIGITS;
}

const expo = (v, d) => v.toExponential(d).replace('e+', 'e');

/* Labels for tick values (null -> ''), one format for all. */
function tickLabels(values) {
  const shown = values.filter((v) => v !== null && v !== undefined && Number.isFinite(v));
  const mags = shown.filter((v) => v !== 0).map(Math.abs);
  if (!mags.length) return values.map((v) => (shown.includes(v) ? '0' : ''));
  const lo = Math.min(...mags);
  const hi = Math.max(...mags);
  const exponential = hi >= 1e5 || lo < 1e-3 || hi / lo >= 1e4;
  const format = exponential ? expo : (v, d) => v.toFixed(d);
  const d = digits(shown, format);
  return values.map((v) => {
    if (v === null || v === undefined || !Number.isFinite(v)) return '';
    return v === 0 ? (exponential ? '0' : (0).toFixed(d)) : format(v, d);
  });
}

/* The labels each chart's axes were last given, by chart (the browser test
 * reads them through drawnTickLabels instead of uPlot's internals). */
const drawn = new WeakMap();

/** uPlot axis.values: the labels of the ticks it passes (axis: the axis index). */
export const axisValues = (u, splits, axis) => {
  const labels = tickLabels(splits);
  if (!drawn.has(u)) drawn.set(u, []);
  drawn.get(u)[axis] = labels;
  return labels;
};

/** The labels axisValues last returned for each axis of chart u ([] for an axis not drawn). */
export const drawnTickLabels = (u) => u.axes.map((_, i) => drawn.get(u)?.[i] || []);
