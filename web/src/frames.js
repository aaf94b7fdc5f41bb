/*
 * frames.js — the frame viewer: GET /v1/sessions/{id}/frame.png at a chosen
 * time, a time scrubber, and play/pause animation (the next frame is requested
 * only after the previous one arrived, so playback never floods the daemon).
 * The PNG is fetched with the bearer token (an <img src> cannot send it) and
 * shown from an object URL. When the build has no renderer the daemon answers
 * 404/422/501: the viewer then shows that message as a placeholder. An
 * exaggeration outside the API's range is reported next to its input (the
 * last frame stays) and not requested.
 */
import { raw, api, ApiError } from './api.js';
import { fmt } from './units.js';
import { numberField } from './number_input.js';

export class FrameViewer {
  constructor(els) {
    this.els = els; /* {img, placeholder, scrub, time, play, view, exaggeration, exaggerationError, tension, status} */
    this.session = null;
    this.playing = false;
    this.url = null;
    this.pending = null;
    this.wanted = null; /* {t, exaggeration} of the next frame to load */
    this.available = null; /* null unknown (or failed for a reason that may pass), true frames load, false none here */
    /* the factor, or undefined (its error shown next to the input) when not a number in the API's range */
    const ex = els.exaggeration;
    this.exaggeration = numberField(ex, { name: 'exaggeration', min: Number(ex.min), max: Number(ex.max) }, els.exaggerationError);
    els.scrub.addEventListener('input', () => this.request(this.scrubTime()));
    els.play.addEventListener('click', () => this.toggle());
    for (const e of [els.view, els.exaggeration, els.tension]) e.addEventListener('change', () => this.request(this.scrubTime()));
  }

  /** The frame controls do something only where frames can be drawn. */
  setControlsEnabled(on) {
    for (const e of [this.els.play, this.els.scrub, this.els.view, this.els.exaggeration, this.els.tension]) e.disabled = !on;
  }

  setSession(session) {
    clearTimeout(this.followTimer);
    this.session = session;
    this.pause();
    this.available = null;
    this.setControlsEnabled(true);
    this.updateRange(session.t || 0);
    this.request(session.t || 0);
  }

  /** No session open: back to the initial placeholder. */
  clear() {
    this.pause();
    clearTimeout(this.followTimer);
    this.session = null;
    this.wanted = null;
    this.els.img.hidden = true;
    this.els.img.removeAttribute('src');
    if (this.url) URL.revokeObjectURL(this.url);
    this.url = null;
    this.els.scrub.max = '0';
    this.els.scrub.value = '0';
    this.els.time.textContent = 't = 0 s';
    this.els.placeholder.hidden = false;
    this.els.placeholder.textContent = 'Open a session to see its frames.';
    this.els.status.textContent = '';
    this.setControlsEnabled(true);
  }

  /** Keep the scrubber's range at [0, latest sample time]. */
  updateRange(tMax) {
    const s = this.els.scrub;
    const atEnd = Number(s.value) >= Number(s.max) - 1e-9;
    if (Number(s.max) === Math.max(tMax, 0)) return;
    s.max = String(Math.max(tMax, 0));
    s.step = 'any';
    if (atEnd && !this.playing) {
      /* follow the newest sample; fetch its frame unless the session has none */
      s.value = s.max;
      this.els.time.textContent = `t = ${fmt(Number(s.max))} s`;
      /* follow the run with at most one frame a second (rendering shares the
       * simulation workers); the trailing call fetches the final frame */
      if (this.available !== false) {
        clearTimeout(this.followTimer);
        const wait = Math.max(0, 1000 - (Date.now() - (this.lastFollow || 0)));
        this.followTimer = setTimeout(() => {
          this.lastFollow = Date.now();
          if (!this.playing && Number(s.value) === Number(s.max)) this.request(Number(s.max));
        }, wait);
      }
    }
  }

  scrubTime() {
    return Number(this.els.scrub.value);
  }

  /** Load the frame at time t (latest request wins; one in flight at a time). */
  request(t) {
    if (!this.session) return;
    this.els.time.textContent = `t = ${fmt(t)} s`;
    const { value: exaggeration } = this.exaggeration();
    if (exaggeration === undefined) {
      this.pause(); /* nothing to play until the input is fixed */
      return;
    }
    this.wanted = { t, exaggeration };
    if (!this.pending) this.pending = this.load();
  }

  async load() {
    while (this.wanted && this.session) {
      const { t, exaggeration } = this.wanted;
      const session = this.session;
      this.wanted = null;
      const img = this.els.img;
      const params = {
        t: t.toFixed(4),
        width: 640,
        height: 360,
        view: this.els.view.value,
        exaggeration,
        color: this.els.tension.checked ? 'tension' : undefined,
      };
      try {
        const resp = await raw('GET', api.frameUrl(session.id, params));
        const blob = await resp.blob();
        if (this.session !== session) continue; /* closed or another session opened meanwhile */
        const url = URL.createObjectURL(blob);
        await new Promise((res, rej) => {
          img.onload = res;
          img.onerror = () => rej(new Error('the frame is not a readable image'));
          img.src = url;
        });
        if (this.url) URL.revokeObjectURL(this.url);
        this.url = url;
        img.dataset.t = String(t);
        this.available = true;
        img.hidden = false;
        this.els.placeholder.hidden = true;
        this.els.status.textContent = `frame at t = ${fmt(t)} s`;
      } catch (e) {
        if (this.session === session) this.showPlaceholder(e);
      }
    }
    this.pending = null;
    if (this.playing) this.advance();
  }

  showPlaceholder(e) {
    const unavailable = e instanceof ApiError && [404, 422, 501].includes(e.status);
    /* a daemon that went away (or a 5xx) may come back: unknown again, so
     * following the run asks again (at most once a second) */
    this.available = unavailable ? false : null;
    this.els.img.hidden = true;
    this.els.placeholder.hidden = false;
    this.els.placeholder.textContent = unavailable
      ? `No frame available — ${e.message}. Frames are drawn for scenarios with vehicle geometry (and builds with the renderer); the plots and spectra work without them.`
      : `Frame could not be loaded: ${e.message}`;
    this.els.placeholder.dataset.status = String(e.status ?? '');
    this.els.status.textContent = 'frames unavailable';
    this.pause();
    /* none here (a point mass, an engine on its dynamometer): Play, the time
     * and the drawing options would do nothing, so they say so (review) */
    if (unavailable) this.setControlsEnabled(false);
  }

  toggle() {
    if (this.playing) this.pause();
    else this.playFrom();
  }

  playFrom() {
    if (!this.session) return;
    const s = this.els.scrub;
    if (Number(s.value) >= Number(s.max)) s.value = '0';
    this.playing = true;
    this.els.play.textContent = '❚❚ Pause';
    this.request(this.scrubTime());
  }

  pause() {
    this.playing = false;
    this.els.play.textContent = '▶ Play';
  }

  /** Next animation step: 1/25 of the run per frame, at most 10 frames/s. */
  advance() {
    const s = this.els.scrub;
    const max = Number(s.max);
    const next = Math.min(max, Number(s.value) + Math.max(max / 25, 0.02));
    setTimeout(() => {
      if (!this.playing) return;
      s.value = String(next);
      this.request(next);
      if (next >= max) this.pause();
    }, 100);
  }
}
