/*
 * stream.js — live samples of one session over Server-Sent Events.
 *
 * EventSource cannot send an Authorization header, so the stream is read with
 * fetch + a ReadableStream SSE parser (@microsoft/fetch-event-source), which
 * sends the bearer token and, on reconnect, Last-Event-ID (event id = sample
 * index) so the daemon resumes exactly after the last sample received. Each
 * "sample" event's data is one row {"index", "t", "values": {name: SI value}};
 * a final "end" event comes when the session stops running.
 *
 * SeriesStore keeps a session's samples columnar (t[], cols[name][]) for uPlot;
 * it is filled first from GET /series (history) and then from the stream.
 */
import { fetchEventSource } from '@microsoft/fetch-event-source';
import { api, authHeaders, ApiError, problemOf, seriesAll } from './api.js';

export class SeriesStore {
  constructor(channels) {
    this.channels = channels; /* [{name, unit, description}] without "t" */
    this.t = [];
    this.cols = Object.fromEntries(channels.map((c) => [c.name, []]));
    this.lastIndex = -1;
    this.version = 0; /* bumped on every change; plots redraw when it moved */
  }

  /** Load history from GET /series (all channels), every `every`-th row. */
  async loadHistory(id, every = 1) {
    const s = await seriesAll(id, every > 1 ? { every } : {});
    this.t = s.t;
    for (const c of this.channels) this.cols[c.name] = s.cols[c.name] || new Array(s.t.length).fill(null);
    this.lastIndex = s.index.length ? s.index[s.index.length - 1] : s.t.length - 1;
    this.version++;
  }

  push(row) {
    if (typeof row.index === 'number') {
      if (row.index <= this.lastIndex) return; /* duplicate after a resume */
      this.lastIndex = row.index;
    } else {
      this.lastIndex++;
    }
    this.t.push(row.t);
    const v = row.values || {};
    for (const c of this.channels) this.cols[c.name].push(v[c.name] ?? null);
    this.version++;
  }

  get length() {
    return this.t.length;
  }
}

class RetryableClose extends Error {}

/**
 * Stream samples of session id into store. onStatus(state, detail) reports
 * the state: "live", "waiting for samples", "reconnecting", "ended" (detail:
 * the session's status in the daemon's end event, undefined without one), or
 * "error" (detail: the daemon's refusal, an ApiError; the stream is over).
 * Returns {stop()}.
 * isFinished() (synchronous) is asked when the daemon closes the stream: true ends it,
 * false reconnects (resuming with Last-Event-ID).
 */
export function streamSession(id, store, { onStatus = () => {}, isFinished = () => false } = {}) {
  const ctrl = new AbortController();
  const url = api.streamUrl(id, { since: store.lastIndex }); /* rows after `since` */
  let ended; /* the session's status in this connection's end event */
  fetchEventSource(url, {
    signal: ctrl.signal,
    headers: authHeaders(),
    openWhenHidden: true,
    async onopen(resp) {
      const ct = resp.headers.get('Content-Type') || '';
      if (resp.ok && ct.startsWith('text/event-stream')) {
        ended = undefined;
        onStatus('live');
        return;
      }
      throw new ApiError(resp.status, await problemOf(resp)); /* fatal: onerror rethrows */
    },
    onmessage(ev) {
      if (ev.event === 'end') {
        ended = endStatus(ev.data); /* the daemon closes the stream next */
        return;
      }
      if (!ev.data) return;
      let row;
      try {
        row = JSON.parse(ev.data);
      } catch {
        return;
      }
      if (row && typeof row.t === 'number') {
        if (row.index === undefined && ev.id !== '') row.index = Number(ev.id);
        store.push(row);
      }
    },
    onclose() {
      /* must not be async: the library does not await it */
      if (ctrl.signal.aborted) return;
      if (isFinished()) {
        onStatus('ended', ended);
        return;
      }
      throw new RetryableClose('stream closed');
    },
    onerror(err) {
      if (err instanceof ApiError) {
        onStatus('error', err);
        throw err;
      }
      if (err instanceof RetryableClose) {
        onStatus('waiting for samples');
        return 300;
      }
      onStatus('reconnecting');
      return 1000;
    },
  }).catch(() => {});
  return { stop: () => ctrl.abort() };
}

/* The session's status in an end event's data ({status, t, index}); undefined when it has none. */
function endStatus(data) {
  try {
    return JSON.parse(data)?.status;
  } catch {
    return undefined;
  }
}
