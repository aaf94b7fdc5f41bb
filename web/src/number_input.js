/*
 * number_input.js — reading a number the user typed, never guessing.
 *
 * A <input type="number"> whose text the browser cannot parse ("abc", "1e")
 * reports value "" and validity.badInput, so a bare Number(input.value) turns
 * it into 0 or "not given". Here such an entry, an empty required field and
 * an entry out of range become an error message that names the field, in the
 * daemon's words ("exaggeration: number in [0, 1000] expected, got '2000'"),
 * so the caller shows it next to the field and sends nothing. numberField()
 * ties that to one input: reading it marks it invalid (with its message),
 * typing in it again takes the mark away. readNumberList / numberListField
 * do the same for a text input of comma-separated numbers ("50000,60000").
 */
import { fmt } from './units.js';

/* A plain decimal numeral, as the daemon's query parameters take them (no 0x10, inf, blanks). */
const NUMERAL = /^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$/;

/** The number a text holds, or NaN when it is not a plain decimal numeral. */
export function parseNumeral(text) {
  const s = String(text).trim();
  return NUMERAL.test(s) ? Number(s) : NaN;
}

function rangeText({ min, max, above }) {
  if (above !== undefined) return ` > ${fmt(above)}`;
  if (min !== undefined && max !== undefined) return ` in [${fmt(min)}, ${fmt(max)}]`;
  if (min !== undefined) return ` ≥ ${fmt(min)}`;
  return max !== undefined ? ` ≤ ${fmt(max)}` : '';
}

/**
 * The number in a numeric or text input: {value} or {error}.
 * name: how the message names the field; min/max: inclusive bounds; above:
 * exclusive lower bound; note: what the bound is, in the message; optional: an empty field gives {value: undefined}.
 */
export function readNumber(input, { name, min, max, above, note, optional = false } = {}) {
  const raw = input.value.trim();
  const expected = `${name}: number${rangeText({ min, max, above })}${note ? ` (${note})` : ''} expected`;
  if (input.validity?.badInput) return { error: `${expected}, got an entry that is not a number` };
  if (raw === '') return optional ? { value: undefined } : { error: `${expected}, got nothing` };
  const v = parseNumeral(raw);
  const out = !Number.isFinite(v) || (min !== undefined && v < min) || (max !== undefined && v > max) || (above !== undefined && v <= above);
  return out ? { error: `${expected}, got '${raw}'` } : { value: v };
}

/**
 * The comma-separated numbers in a text input: {value: [numbers]} or {error}.
 * name, min, max, optional: as readNumber's; most: the most entries taken.
 */
export function readNumberList(input, { name, min, max, most = Infinity, optional = false } = {}) {
  const raw = input.value.trim();
  const count = Number.isFinite(most) ? `1 to ${most} ` : '';
  const expected = `${name}: ${count}comma-separated numbers${rangeText({ min, max })} expected`;
  if (raw === '') return optional ? { value: undefined } : { error: `${expected}, got nothing` };
  const items = raw.split(',').map((s) => s.trim());
  const values = items.map(parseNumeral);
  const bad = items.findIndex((s, i) => {
    const v = values[i];
    return !Number.isFinite(v) || (min !== undefined && v < min) || (max !== undefined && v > max);
  });
  if (bad >= 0) return { error: `${expected}, got ${items[bad] === '' ? 'an empty entry' : `'${items[bad]}'`}` };
  if (values.length > most) return { error: `${expected}, got ${values.length}` };
  return { value: values };
}

/* Mark an input invalid with `message`, shown in the element `msg` (null: shown elsewhere); no message clears. */
function mark(input, msg, message) {
  input.classList.toggle('invalid', !!message);
  input.setAttribute('aria-invalid', message ? 'true' : 'false');
  if (!msg) return;
  msg.textContent = message || '';
  msg.hidden = !message;
}

/**
 * A numeric input read with readNumber's options: the returned function gives
 * {value} or {error} and marks the input (message in `msg`, or null when the
 * caller shows it); an edit takes the mark away until the next read.
 */
export function numberField(input, options, msg = null) {
  return markedField(readNumber, input, options, msg);
}

/** numberField for a list of comma-separated numbers (readNumberList's options, or a function giving them). */
export function numberListField(input, options, msg = null) {
  return markedField(readNumberList, input, options, msg);
}

/* Mark an input from a field's message (a daemon's error about it): an edit takes the mark away. */
export const markInvalid = (input, message, msg = null) => mark(input, msg, message);

/* Mark the inputs a daemon's problem names: byPointer maps an errors[].pointer
   ('/to', '/duration') to its input. Anything but an ApiError marks nothing. */
export function markFromProblem(err, byPointer) {
  for (const x of err?.errors || []) if (byPointer[x.pointer]) markInvalid(byPointer[x.pointer], x.message);
}

/* options: an object, or a function giving it at each read (a range known later) */
function markedField(read, input, options, msg) {
  input.addEventListener('input', () => mark(input, msg, ''));
  return () => {
    const r = read(input, typeof options === 'function' ? options() : options);
    mark(input, msg, r.error);
    return r;
  };
}
