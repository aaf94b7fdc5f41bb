/*
 * fft_controls.js — the FFT panel's form: channel (the hull's vertical
 * acceleration by default, as in the paper's Figs. 13-14), time window and
 * display limit, read and checked here and drawn by FftPanel (fft.js).
 * Compute waits until the open session has two stored samples (update).
 */
import { ApiError } from './api.js';
import { $ } from './dom.js';
import { hideError, showError } from './messages.js';
import { markFromProblem, numberField } from './number_input.js';
import { fillChannelSelect } from './channels.js';

/* the fewest stored rows a spectrum is computed from */
const MIN_SAMPLES = 2;

function pickFftDefault(chans) {
  const names = chans.map((c) => c.name);
  /* the paper's spectra (Figs. 13-14) are of the hull's vertical acceleration */
  return names.find((n) => n === 'hull.accel_z') || names.find((n) => /hull.*acc|accel/.test(n)) || names[0];
}

export function initFftControls(state, fft) {
  const field = (id, name) => numberField($(id), { name, min: 0, optional: true });
  const fields = [field('fft-from', 'from'), field('fft-to', 'to'), field('fft-fmax', 'show up to')];

  async function onFft() {
    const box = $('fft-error');
    hideError(box);
    const read = fields.map((f) => f());
    const errors = read.map((r) => r.error).filter(Boolean);
    const [from, to, fmax] = read.map((r) => r.value);
    try {
      if (errors.length) throw new ApiError(0, { title: 'Not computed', detail: errors.join('; ') });
      await fft.compute(state.session, $('fft-channel').value, from, to, { fmax, log: $('fft-log').checked });
    } catch (e) {
      fft.clear(); /* the last spectrum is not the answer to this request */
      /* the daemon names the bound at fault (e.g. /to: more samples than --max-samples): mark it */
      markFromProblem(e, { '/from': $('fft-from'), '/to': $('fft-to') });
      showError(box, e);
    }
  }

  /* Compute is enabled once the open session has stored MIN_SAMPLES rows (a
   * spectrum needs them); the hint says why not. Called every 300 ms (main.js):
   * the button and the hint are written only when they change. */
  function update() {
    const few = !!state.session && (state.store?.length || 0) < MIN_SAMPLES;
    const off = !state.session || few;
    if ($('fft-btn').disabled !== off) $('fft-btn').disabled = off;
    const hint = few ? `no spectrum before ${MIN_SAMPLES} stored samples: step or run the session first` : '';
    if ($('fft-hint').textContent !== hint) {
      $('fft-hint').textContent = hint;
      $('fft-hint').hidden = !hint;
    }
  }

  /* A session was opened with channels `chans`. */
  function open(chans) {
    fillChannelSelect($('fft-channel'), chans, pickFftDefault(chans));
    update();
    fft.clear();
    hideError($('fft-error'));
  }

  /* No session open. */
  function close() {
    fft.clear();
    hideError($('fft-error'));
    $('fft-channel').replaceChildren();
    update();
  }

  $('fft-btn').addEventListener('click', onFft);

  return { open, close, update };
}
