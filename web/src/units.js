/*
 * units.js — display-only unit conversion. The API speaks SI (every channel
 * carries its SI unit); the dashboard converts to mph / rpm / km/h only when
 * drawing, never when sending. One table: SI unit -> display choices.
 */

const RAD_S_TO_RPM = 60 / (2 * Math.PI);
const MS_TO_MPH = 1 / 0.44704; /* 1 mph = 0.44704 m/s exactly */

/* SI unit -> [{label, factor}] ; the first is the default display unit. */
const DISPLAY = {
  'm/s': [
    { label: 'mph', factor: MS_TO_MPH },
    { label: 'm/s', factor: 1 },
    { label: 'km/h', factor: 3.6 },
  ],
  'rad/s': [
    { label: 'rpm', factor: RAD_S_TO_RPM },
    { label: 'rad/s', factor: 1 },
  ],
  rad: [
    { label: 'deg', factor: 180 / Math.PI },
    { label: 'rad', factor: 1 },
  ],
  W: [
    { label: 'kW', factor: 1e-3 },
    { label: 'W', factor: 1 },
  ],
  Pa: [
    { label: 'kPa', factor: 1e-3 },
    { label: 'Pa', factor: 1 },
  ],
  /* dimensionless (gear number, ratios, efficiencies): no unit label */
  1: [{ label: '', factor: 1 }],
};

/* The user's choice per SI unit (e.g. {'m/s': 'mph'}), kept in localStorage. */
const PREF_KEY = 'tanksim.units';

function prefs() {
  try {
    return JSON.parse(localStorage.getItem(PREF_KEY) || '{}');
  } catch {
    return {};
  }
}

export function choices(siUnit) {
  return DISPLAY[siUnit] || [{ label: siUnit || '', factor: 1 }];
}

/** " [mph]", or "" for a dimensionless quantity. */
export const bracket = (label) => (label ? ` [${label}]` : '');

/** {label, factor} for showing values of an SI unit. */
export function display(siUnit) {
  const list = choices(siUnit);
  const want = prefs()[siUnit];
  return list.find((c) => c.label === want) || list[0];
}

/** The event sent on window when a display unit changes (detail: {siUnit, label}). */
export const UNITS_CHANGED = 'tanksim-units';

export function setDisplay(siUnit, label) {
  const p = prefs();
  p[siUnit] = label;
  localStorage.setItem(PREF_KEY, JSON.stringify(p));
  window.dispatchEvent(new CustomEvent(UNITS_CHANGED, { detail: { siUnit, label } }));
}

export function convertible(siUnit) {
  return (DISPLAY[siUnit] || []).length > 1;
}

/** How a value the daemon gives in `unit` is shown: {label, factor} (factor:
 * from `unit` to the chosen display unit), or null when no toggle covers it.
 * `unit` is an SI unit of the table or one of its display units: the run
 * figures come in both (engine_speed_max in rad/s, top_speed_mph in mph). */
export function displayFrom(unit) {
  const si = convertible(unit) ? unit : Object.keys(DISPLAY).find((k) => convertible(k) && DISPLAY[k].some((c) => c.label === unit));
  if (!si) return null;
  const d = display(si);
  if (d.label === unit) return { label: d.label, factor: 1, si };
  const toSi = si === unit ? 1 : 1 / DISPLAY[si].find((c) => c.label === unit).factor;
  return { label: d.label, factor: toSi * d.factor, si };
}

/** SI values (null = no sample) in the display unit {factor}. */
export function toDisplay(values, d) {
  return d.factor === 1 ? values : extendDisplay([], values, d);
}

/** `shown`, the first shown.length of `values` in the display unit {factor},
 * with the rest of `values` appended, converted: a column that grows costs
 * only its new rows. */
export function extendDisplay(shown, values, { factor }) {
  for (let i = shown.length; i < values.length; i++) shown.push(values[i] === null ? null : values[i] * factor);
  return shown;
}

/** Format a number compactly for tables and labels: `digits` significant
 * digits, but whole units kept from 10^digits up to 1e9 (a tension of
 * 146,613 N reads "146613", not "1.47e+5"), exponential beyond that range
 * and below 1e-3 with the same significant digits. */
export function fmt(v, digits = 4) {
  if (v === null || v === undefined || Number.isNaN(v)) return '—';
  if (v === 0) return '0';
  const a = Math.abs(v);
  if (a >= 1e9 || a < 1e-3) return v.toExponential(digits - 1).replace(/\.?0+e/, 'e').replace('e+', 'e');
  if (a >= 10 ** digits) return Math.round(v).toString();
  return Number(v.toPrecision(digits)).toString();
}

/** A time on a run's sample grid [s], to the grid's decimals (500 Hz: 3), so that
 * 11.005 and 21.005 s both show their last 5 ms (fmt's 4 digits gave 11.01 and 21). */
export function fmtTime(t, rate) {
  if (!(rate > 0) || !Number.isFinite(t)) return fmt(t);
  const dec = Math.min(9, Math.max(0, Math.ceil(Math.log10(rate) - 1e-9)));
  return Number(t.toFixed(dec)).toString();
}
