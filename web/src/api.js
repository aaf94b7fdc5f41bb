/*
 * api.js — the dashboard's only door to tanksimd's REST API (api/openapi.yaml).
 *
 * Every call goes through request(): it adds the bearer token (entered once,
 * kept in localStorage under "tanksim.token"), parses JSON bodies, and turns
 * any non-2xx answer into an ApiError carrying the RFC 9457 problem document
 * (title, detail, errors[{pointer, message}]) so the UI can say what went
 * wrong and highlight the field a pointer names.
 */

const TOKEN_KEY = 'tanksim.token';

export function getToken() {
  try {
    return localStorage.getItem(TOKEN_KEY) || '';
  } catch {
    return '';
  }
}

export function setToken(token) {
  if (token) localStorage.setItem(TOKEN_KEY, token);
  else localStorage.removeItem(TOKEN_KEY);
}

export function authHeaders() {
  const t = getToken();
  return t ? { Authorization: `Bearer ${t}` } : {};
}

/** An API failure: HTTP status plus the problem document (or a synthesized one). */
export class ApiError extends Error {
  constructor(status, problem) {
    const title = problem.title || `HTTP ${status}`;
    super(problem.detail ? `${title}: ${problem.detail}` : title);
    this.status = status;
    this.problem = problem;
    this.errors = Array.isArray(problem.errors) ? problem.errors : [];
  }
}

/** The problem document of a failed Response (a synthesized one when the body is not JSON). */
export async function problemOf(resp) {
  const text = await resp.text().catch(() => '');
  try {
    const doc = JSON.parse(text);
    if (doc && typeof doc === 'object') return doc;
  } catch {
    /* not JSON: fall through */
  }
  return { title: `${resp.status} ${resp.statusText}`.trim(), detail: text.slice(0, 300) };
}

/** fetch + token + problem handling. Returns the Response of a 2xx answer. */
export async function raw(method, path, { body, headers, signal } = {}) {
  const h = { ...authHeaders(), ...(headers || {}) };
  let payload;
  if (body !== undefined) {
    h['Content-Type'] = 'application/json';
    payload = JSON.stringify(body);
  }
  let resp;
  try {
    resp = await fetch(path, { method, headers: h, body: payload, signal });
  } catch (e) {
    if (e.name === 'AbortError') throw e;
    throw new ApiError(0, { title: 'Server unreachable', detail: `${method} ${path}: ${e.message}` });
  }
  if (!resp.ok) throw new ApiError(resp.status, await problemOf(resp));
  return resp;
}

export async function request(method, path, opts) {
  const resp = await raw(method, path, opts);
  if (resp.status === 204) return null;
  const ct = resp.headers.get('Content-Type') || '';
  return ct.includes('json') ? resp.json() : resp.text();
}

const enc = encodeURIComponent;
const qs = (params) => {
  const parts = Object.entries(params)
    .filter(([, v]) => v !== undefined && v !== null && v !== '')
    .map(([k, v]) => `${enc(k)}=${enc(v)}`);
  return parts.length ? `?${parts.join('&')}` : '';
};

export const api = {
  health: () => request('GET', '/v1/health'),
  presets: () => request('GET', '/v1/presets'),
  preset: (name) => request('GET', `/v1/presets/${enc(name)}`),
  schema: () => request('GET', '/v1/schema'),
  sessions: (pageToken) => request('GET', `/v1/sessions${qs({ page_size: 100, page_token: pageToken })}`),
  session: (id) => request('GET', `/v1/sessions/${enc(id)}`),
  createSession: (doc) => request('POST', '/v1/sessions', { body: doc }),
  deleteSession: (id) => request('DELETE', `/v1/sessions/${enc(id)}`),
  step: (id, duration) => request('POST', `/v1/sessions/${enc(id)}/step`, { body: { duration } }),
  /* until [s]: end time (default: the config's duration); rtf: real-time factor cap (0/undefined = none) */
  run: (id, until, rtf) =>
    request('POST', `/v1/sessions/${enc(id)}/run`, {
      body: { ...(until === undefined ? {} : { until }), ...(rtf ? { real_time_factor: rtf } : {}) },
    }),
  /* analyses (operations): doc is a run config, e.g. {preset: 'engine-map-lhr10'} */
  engineMap: (doc) => request('POST', '/v1/engine-map', { body: doc }),
  /* params: {schedule_mass: '50000,60000'} or {schedule_grade: ...} (optional) */
  tune: (doc, params = {}) => request('POST', `/v1/tune${qs(params)}`, { body: doc }),
  /* stored analyses, newest first: what was asked, not the request body nor results (GET the operation for those) */
  analyses: () => request('GET', '/v1/analyses'),
  deleteAnalysis: (id) => request('DELETE', `/v1/analyses/${enc(id)}`),
  operation: (opId) => request('GET', `/v1/operations/${enc(opId)}`),
  cancel: (opId) => request('POST', `/v1/operations/${enc(opId)}:cancel`),
  series: (id, params) => request('GET', `/v1/sessions/${enc(id)}/series${qs({ format: 'json', ...params })}`),
  summary: (id) => request('GET', `/v1/sessions/${enc(id)}/summary`),
  fft: (id, params) => request('GET', `/v1/sessions/${enc(id)}/fft${qs(params)}`),
  streamUrl: (id, params) => `/v1/sessions/${enc(id)}/stream${qs(params)}`,
  frameUrl: (id, params) => `/v1/sessions/${enc(id)}/frame.png${qs(params)}`,
};

/** Fetch every page of the session list. */
export async function allSessions() {
  const out = [];
  let token;
  for (let guard = 0; guard < 50; guard++) {
    const page = await api.sessions(token);
    out.push(...(page.sessions || []));
    token = page.next_page_token;
    if (!token) break;
  }
  return out;
}

/**
 * Columnar series of a session: {t: Float64Array-like, index: [], cols: {name: []}}.
 * Follows next_page_token until the range is complete.
 */
export async function seriesAll(id, params) {
  const res = { t: [], index: [], cols: {} };
  let token;
  for (let guard = 0; guard < 1000; guard++) {
    const doc = await api.series(id, { ...params, page_token: token });
    appendSeries(res, doc);
    token = doc.next_page_token;
    if (!token) break;
  }
  return res;
}

function appendSeries(res, doc) {
  const chans = doc.channels || [];
  for (const c of chans) {
    if (c.name === 't') {
      res.t.push(...c.values);
    } else {
      if (!res.cols[c.name]) res.cols[c.name] = [];
      res.cols[c.name].push(...c.values);
    }
  }
  if (Array.isArray(doc.index)) res.index.push(...doc.index);
}
