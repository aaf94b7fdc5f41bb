/*
 * tune_controls.js — the Analyses panel's tuning form: a config preset whose
 * resolved config can be tuned (GET /v1/presets' powertrain-and-vehicle
 * scenarios, kind coupled, which carry the IVS controller; setPresets), and optionally a gain-schedule variable
 * (mass or grade) with its comma-separated values, checked here before
 * anything is sent (number_input.js) and by the daemon again; POST /v1/tune,
 * followed by analysis_op.js, its result shown by showTuning (tune.js);
 * changed, showStored, attach, reset, shown: see analysis_op.js. Showing a
 * stored tuning puts the preset and the schedule it was asked with back in
 * the form (its operation's metadata.request), or the form said other
 * inputs than those of the tuning shown (review).
 */
import { api } from './api.js';
import { $, presetOptions, selectIf } from './dom.js';
import { hideError } from './messages.js';
import { markFromProblem, markInvalid, numberListField } from './number_input.js';
import { initAnalysisOp } from './analysis_op.js';
import { fieldRange } from './schema_form.js';
import { showTuning } from './tune.js';

/* The schedule variables: query parameter and the config field whose range
 * (GET /v1/schema, state.schema) each value must be in; the daemon takes 1 to
 * 16 values. */
const SCHEDULE = {
  mass: { param: 'schedule_mass', pointer: '/vehicle/mass', name: 'schedule masses [kg]', placeholder: 'e.g. 50000,60000,70000' },
  grade: { param: 'schedule_grade', pointer: '/vehicle/grade', name: 'schedule grades [rad]', placeholder: 'e.g. 0,0.05,0.1' },
};
const MOST = 16;

export function initTuneControls(state, { changed }) {
  const op = initAnalysisOp(state, 'tune', 'tune', { onDone: (doc) => showTuning($('tune-result'), doc), onClear: () => $('tune-result').replaceChildren(), changed });
  const input = $('tune-values');
  const fields = Object.fromEntries(
    Object.entries(SCHEDULE).map(([k, s]) => [k, numberListField(input, () => ({ name: s.name, most: MOST, ...fieldRange(state.schema, s.pointer) }), $('tune-values-error'))]),
  );

  function onVar() {
    const s = SCHEDULE[$('tune-var').value];
    input.disabled = !s;
    input.placeholder = s ? s.placeholder : 'no schedule';
    markInvalid(input, '', $('tune-values-error'));
  }

  function onRun() {
    const box = $('tune-error');
    hideError(box);
    const v = $('tune-var').value;
    const s = SCHEDULE[v];
    const read = s ? fields[v]() : { value: undefined };
    if (read.error) return; /* shown on the field */
    const params = s ? { [s.param]: read.value.join(',') } : {};
    op.start(async () => {
      try {
        return await api.tune({ preset: $('tune-preset').value }, params);
      } catch (e) {
        /* the daemon names the query parameter: mark the values field */
        if (s) markFromProblem(e, { [`/${s.param}`]: input }); /* the message is in the error box */
        throw e;
      }
    });
  }

  /* The form's inputs as stored operation `stored` asked: its preset (left when the list has no such
     option) and its schedule variable and values (the query text), or none. */
  function restore(stored) {
    const req = stored.metadata?.request || {};
    selectIf($('tune-preset'), req.body?.preset);
    const v = Object.keys(SCHEDULE).find((k) => req[SCHEDULE[k].param] !== undefined) || '';
    $('tune-var').value = v;
    onVar();
    input.value = v ? String(req[SCHEDULE[v].param]) : '';
  }

  $('tune-var').addEventListener('change', onVar);
  $('tune-run').addEventListener('click', onRun);
  onVar();
  return {
    setPresets: (presets) => {
      presetOptions($('tune-preset'), presets.filter((p) => p.kind === 'coupled'));
      op.presetsSet();
    },
    showStored: (stored) => {
      restore(stored);
      op.showStored(stored);
    },
    attach: op.attach,
    reset: op.reset,
    shown: op.shown,
  };
}
