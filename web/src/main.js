/*
 * main.js — the tanksim dashboard: wires the panels to the REST API.
 *
 * Sessions list (polled), "new session" form generated from /v1/schema,
 * run controls (step, run to end with a progress bar fed by polling the
 * long-running operation, cancel), live plots over the SSE stream, FFT,
 * frame viewer and the multi-session compare overlay. Every API failure is
 * shown in words; problem+json errors[].pointer marks the form field. The
 * open session's header follows its run (operation polling, and the session
 * list's polling for runs started elsewhere); a deleted session is cleared
 * from every panel.
 */
import 'uplot/dist/uPlot.min.css';
import './style.css';
import { api, ApiError, allSessions, getToken, setToken } from './api.js';
import { SchemaForm } from './schema_form.js';
import { SeriesStore, streamSession } from './stream.js';
import { LivePlots, defaultPicks } from './plots.js';
import { FftPanel } from './fft.js';
import { FrameViewer } from './frames.js';
import { ComparePanel } from './compare.js';
import { bracket, choices, display, setDisplay, fmt } from './units.js';
import { markInput, readNumber } from './number_input.js';

const $ = (id) => document.getElementById(id);
const HISTORY_POINTS = 50000;

const state = {
  form: null,
  sessions: [],
  compare: new Set(), /* ids ticked for Compare */
  session: null, /* the open session object */
  store: null,
  stream: null,
  picks: [],
  op: null, /* {id, timer} of the operation being polled */
};

/* ---------- messages ---------- */

function showError(box, err) {
  const e = err instanceof ApiError ? err : new ApiError(0, { title: 'Error', detail: String(err?.message || err) });
  box.replaceChildren();
  const head = document.createElement('strong');
  /* with a field list the detail repeats its first entry: show the title only */
  head.textContent = e.errors.length ? e.problem.title || e.message : e.message;
  box.append(head);
  if (e.errors.length) {
    const ul = document.createElement('ul');
    for (const x of e.errors) {
      const li = document.createElement('li');
      const code = document.createElement('code');
      code.textContent = x.pointer || '(document)';
      li.append(code, ` — ${x.message}`);
      ul.append(li);
    }
    box.append(ul);
  }
  box.hidden = false;
  if (e.status === 401) {
    banner(getToken() ? 'The daemon rejected the saved API token: enter the right one at the top right and press Save.' : 'The daemon requires an API token: enter it at the top right and press Save.');
    $('token-input').classList.add('attention');
    $('token-input').focus();
  }
}

const hideError = (box) => {
  box.hidden = true;
  box.replaceChildren();
};

function banner(text) {
  const b = $('banner');
  b.textContent = text || '';
  b.hidden = !text;
}

/* ---------- token ---------- */

function initToken() {
  $('token-input').value = getToken();
  $('token-form').addEventListener('submit', (ev) => {
    ev.preventDefault();
    setToken($('token-input').value.trim());
    banner('');
    $('token-input').classList.remove('attention');
    boot();
  });
}

/* ---------- sessions list ---------- */

/* Why the list is empty: no sessions, or the daemon refused to list them. */
function listMessage(e) {
  if (!e) return 'No sessions yet — create one below.';
  if (e.status !== 401) return `Could not load the sessions: ${e.message}`;
  return getToken()
    ? 'Token rejected: the daemon did not accept the saved API token. Enter the right one under “API token” at the top and press Save.'
    : 'Authentication required: the daemon was started with an API token. Enter it under “API token” at the top and press Save.';
}

async function refreshSessions() {
  const tbody = $('session-table').querySelector('tbody');
  const seen = openSnapshot();
  try {
    state.sessions = await allSessions();
  } catch (e) {
    if (e.status === 401) showError($('create-error'), e);
    tbody.replaceChildren();
    $('sessions-empty').textContent = listMessage(e);
    $('sessions-empty').dataset.problem = String(e.status ?? '');
    $('sessions-empty').hidden = false;
    return;
  }
  $('sessions-empty').textContent = listMessage(null);
  delete $('sessions-empty').dataset.problem;
  tbody.replaceChildren();
  for (const s of state.sessions) {
    const tr = document.createElement('tr');
    tr.dataset.id = s.id;
    if (state.session && state.session.id === s.id) tr.classList.add('selected');
    const cb = document.createElement('input');
    cb.type = 'checkbox';
    cb.className = 'cmp';
    cb.checked = state.compare.has(s.id);
    cb.title = 'include in Compare';
    cb.addEventListener('click', (ev) => ev.stopPropagation());
    cb.addEventListener('change', () => {
      if (cb.checked) state.compare.add(s.id);
      else state.compare.delete(s.id);
      updateCompareInfo();
    });
    const cells = [
      cb,
      mono(String(s.id).slice(0, 8)),
      text(s.preset || '—'),
      pill(s.status),
      text(s.t !== undefined ? `${fmt(s.t, 4)}${s.duration ? ` / ${fmt(s.duration)}` : ''}` : '—'),
    ];
    cells.forEach((c, i) => {
      const td = document.createElement('td');
      if (i === 4) td.className = 'num';
      td.append(c);
      tr.append(td);
    });
    tr.addEventListener('click', () => openSession(s.id));
    tbody.append(tr);
  }
  $('sessions-empty').hidden = state.sessions.length > 0;
  for (const id of [...state.compare]) if (!state.sessions.some((s) => s.id === id)) state.compare.delete(id);
  updateCompareInfo();
  followOpenSession(seen);
}

/* What the open session looked like when a list request left. */
function openSnapshot() {
  const s = state.session;
  return s && { s, status: s.status, t: s.t, op: state.op };
}

/* Keep the open session in step with the list (a run or a delete by another
 * client), unless it changed here while the list was on its way (then the
 * list is the older news) or an operation's polling already follows it. */
function followOpenSession(seen) {
  const s = state.session;
  if (!s || !seen || seen.s !== s || seen.status !== s.status || seen.t !== s.t || seen.op || state.op) return;
  const sum = state.sessions.find((x) => x.id === s.id);
  if (!sum) {
    closeSession(`Session ${s.id} no longer exists (deleted).`);
    return;
  }
  if (sum.status === s.status && sum.t === s.t) return;
  Object.assign(s, { status: sum.status, t: sum.t, index: sum.index, error: sum.error, operation: sum.operation });
  renderSessionHeader();
  if (sum.status === 'running' && sum.operation) {
    pollOperation(sum.operation);
    startStream();
  }
}

const text = (s) => document.createTextNode(s);
function mono(s) {
  const e = document.createElement('span');
  e.className = 'mono';
  e.textContent = s;
  return e;
}
function pill(status) {
  const e = document.createElement('span');
  e.className = `pill st-${status || 'unknown'}`;
  e.textContent = status || '?';
  return e;
}

/* ---------- create form ---------- */

async function initCreateForm() {
  const [schema, presets] = await Promise.all([api.schema(), api.presets()]);
  state.form = new SchemaForm($('schema-form'), schema);
  const list = presets.presets || [];
  const sel = $('preset-select');
  sel.replaceChildren();
  for (const p of list) {
    const o = document.createElement('option');
    o.value = p.name;
    o.textContent = p.name;
    o.title = p.description || '';
    /* a preset that serves other commands only (the eigenanalysis ones: POST /v1/modes)
       stays visible but cannot start a session */
    if (Array.isArray(p.commands) && !p.commands.includes('session')) {
      o.disabled = true;
      o.textContent = `${p.name} (${p.commands.join(', ')} only)`;
    }
    sel.append(o);
  }
  sel.onchange = () => loadPreset(list);
  $('reset-form').onclick = () => loadPreset(list);
  await loadPreset(list);
}

async function loadPreset(list) {
  const name = $('preset-select').value;
  const meta = list.find((p) => p.name === name);
  $('preset-desc').textContent = [meta?.kind && `scenario ${meta.kind}.`, meta?.description].filter(Boolean).join(' ');
  hideError($('create-error'));
  let doc = {};
  if (name) {
    try {
      doc = (await api.preset(name)).config; /* the resolved document (GET /v1/presets/{name}) */
    } catch (e) {
      showError($('create-error'), e);
    }
  }
  state.form.setBase(doc);
}

async function onCreate(ev) {
  ev.preventDefault();
  const box = $('create-error');
  hideError(box);
  if (!state.form) {
    showError(box, new ApiError(0, { title: 'No form', detail: 'the run-config schema could not be loaded (see above); reload the page' }));
    return;
  }
  state.form.clearErrors();
  const { doc: overrides, errors } = state.form.overrides();
  if (errors.length) {
    state.form.showErrors(errors);
    showError(box, new ApiError(0, { title: 'Not sent: fix the marked fields', errors }));
    return;
  }
  const doc = { preset: $('preset-select').value || undefined, ...overrides };
  $('create-btn').disabled = true;
  try {
    const s = await api.createSession(doc);
    await refreshSessions();
    await openSession(s.id, s);
  } catch (e) {
    const unmatched = e instanceof ApiError ? state.form.showErrors(e.errors) : [];
    showError(box, e);
    box.dataset.unmatched = String(unmatched.length);
  } finally {
    $('create-btn').disabled = false;
  }
}

/* ---------- the open session ---------- */

function channelsOf(s) {
  return (s.channels || []).filter((c) => c.name !== 't');
}

async function openSession(id, given) {
  hideError($('session-error'));
  let s = given;
  try {
    if (!s || !s.channels) s = await api.session(id);
  } catch (e) {
    showError($('session-error'), e);
    return;
  }
  state.stream?.stop();
  state.stream = null;
  stopOpPolling();
  state.session = s;
  for (const tr of $('session-table').querySelectorAll('tr[data-id]')) tr.classList.toggle('selected', tr.dataset.id === s.id);
  renderSessionHeader();
  const chans = channelsOf(s);
  state.store = new SeriesStore(chans);
  state.picks = defaultPicks(chans);
  renderChannelPicker();
  renderUnitToggles();
  fillChannelSelect($('fft-channel'), chans, pickFftDefault(chans));
  $('fft-btn').disabled = false;
  fft.clear();
  hideError($('fft-error'));
  try {
    /* long histories are thinned to about HISTORY_POINTS rows; live rows come at full rate */
    const every = Math.max(1, Math.ceil((s.index || 0) / HISTORY_POINTS));
    if ((s.t || 0) > 0 || (s.index || 0) > 0) await state.store.loadHistory(s.id, every);
  } catch (e) {
    showError($('session-error'), e);
  }
  if (state.session !== s) return; /* another session was opened meanwhile */
  $('plots-empty').hidden = true;
  plots.show(state.store, state.picks);
  updateSampleCount();
  frames.setSession(s);
  updateCompareChannels();
  startStream();
  if (s.status === 'running' && s.operation) pollOperation(s.operation);
}

function pickFftDefault(chans) {
  const names = chans.map((c) => c.name);
  /* the paper's spectra (Figs. 13-14) are of the hull's vertical acceleration */
  return names.find((n) => n === 'hull.accel_z') || names.find((n) => /hull.*acc|accel/.test(n)) || names[0];
}

/* Options "name [display unit]": the unit the charts draw the channel in. */
function fillChannelSelect(sel, chans, selected) {
  const keep = selected || sel.value;
  sel.replaceChildren();
  for (const c of chans) {
    const o = document.createElement('option');
    o.value = c.name;
    o.dataset.unit = c.unit;
    o.textContent = `${c.name}${bracket(display(c.unit).label)}`;
    sel.append(o);
  }
  if (chans.some((c) => c.name === keep)) sel.value = keep;
}

/* After a unit toggle: the same options with the new display units. */
function relabelChannelSelect(sel) {
  for (const o of sel.options) o.textContent = `${o.value}${bracket(display(o.dataset.unit).label)}`;
}

/* Title, status, time, buttons and progress of the open session; `gone`: what to say when none is. */
function renderSessionHeader(gone) {
  const s = state.session;
  const open = !!s;
  $('session-title').textContent = open ? `Session ${String(s.id).slice(0, 8)}` : 'No session open';
  const st = $('session-status');
  const status = s?.status || (gone ? 'deleted' : '');
  st.className = `pill st-${status || 'none'}`;
  st.textContent = status;
  const dur = s?.config?.run?.duration;
  const fid = s?.config?.track?.fidelity;
  const kind = s?.config?.run?.kind;
  $('session-meta').textContent = open
    ? [
        `preset ${s.preset || '—'}`,
        kind && `scenario ${kind}`,
        fid && `track ${fid}`,
        `t = ${fmt(s.t || 0)} s${dur ? ` of ${fmt(dur)} s` : ''}`,
        s.error ? `error: ${s.error}` : '',
      ]
        .filter(Boolean)
        .join(' · ')
    : gone || '';
  const running = s?.status === 'running' || !!state.op;
  const ended = open && dur !== undefined && (s.t || 0) >= dur - 1e-9;
  $('step-btn').disabled = !open || running || ended;
  $('run-btn').disabled = !open || running || ended;
  $('cancel-btn').disabled = !state.op;
  $('delete-session').disabled = !open;
  renderProgress(state.op?.meta);
}

/* The bar shows t / run duration (meta: the run operation's metadata, for its speed). */
function renderProgress(meta) {
  const s = state.session;
  const dur = s?.config?.run?.duration;
  if (!s) resetProgress();
  else if (dur) setProgress((s.t || 0) / dur, meta);
}

/* t / duration only moves forward, also when a paused run continues (an
 * operation's own progress restarts at 0 from where it was started). */
function setProgress(frac, meta) {
  const pct = Math.max(0, Math.min(100, frac * 100));
  $('progress-bar').style.width = `${pct}%`;
  let txt = `${pct.toFixed(pct >= 99.95 || pct === 0 ? 0 : 1)} %`;
  if (meta?.t !== undefined) txt += ` · t = ${fmt(meta.t)} s`;
  if (meta?.real_time_factor) txt += ` · ${fmt(meta.real_time_factor, 3)}× real time`;
  $('progress-text').textContent = txt;
  $('progress-bar').parentElement.dataset.percent = pct.toFixed(1);
}

function resetProgress() {
  $('progress-bar').style.width = '0';
  $('progress-text').textContent = '—';
  delete $('progress-text').dataset.outcome;
  delete $('progress-bar').parentElement.dataset.percent;
}

async function refreshSession() {
  if (!state.session) return;
  try {
    const s = await api.session(state.session.id);
    if (!state.session || s.id !== state.session.id) return;
    state.session = s;
    renderSessionHeader();
    frames.updateRange(s.t || 0);
  } catch (e) {
    showError($('session-error'), e);
  }
}

/* ---------- stream ---------- */

function startStream() {
  if (!state.session || state.stream) return;
  const id = state.session.id;
  const handle = streamSession(id, state.store, {
    onStatus: (st) => {
      if (state.stream !== handle) return; /* a stopped stream's last words */
      const e = $('stream-status');
      e.textContent = `stream: ${st}`;
      e.className = `pill ${st === 'live' ? 'st-running' : 'muted'}`;
      if (st === 'ended') state.stream = null;
    },
    /* The daemon ends a stream when the session is not running; reconnect
     * only while a run of this session is being polled. */
    isFinished: () => !(state.op && state.op.sessionId === id),
  });
  state.stream = handle;
}

function updateSampleCount() {
  const n = state.store?.length || 0;
  const e = $('sample-count');
  e.textContent = `${n} samples${n ? ` · t = ${fmt(state.store.t[n - 1])} s` : ''}`;
  e.dataset.count = String(n);
}

/* ---------- run controls ---------- */

async function onStep() {
  const s = state.session;
  hideError($('session-error'));
  const { value: duration, error } = readNumber($('step-duration'), { name: 'step duration [s]', above: 0 });
  markInput($('step-duration'), null, error);
  if (error) {
    showError($('session-error'), new ApiError(0, { title: 'Not stepped', detail: error }));
    return;
  }
  try {
    await api.step(s.id, duration); /* synchronous: the answer is the session's new state */
    await refreshSession();
    startStream(); /* fetch the new rows (the stream ends when they are sent) */
    refreshSessions();
  } catch (e) {
    showError($('session-error'), e);
  }
}

async function onRun() {
  const s = state.session;
  hideError($('session-error'));
  try {
    const pace = Number($('run-pace').value) || undefined;
    const op = await api.run(s.id, s.config?.run?.duration, pace);
    pollOperation(op.id, op);
    startStream();
  } catch (e) {
    showError($('session-error'), e);
  }
}

/* google.rpc code 1 = CANCELLED (the daemon also sends a problem type). */
const isCancelled = (err) => err.code === 1 || /cancel/i.test(err.type || '');

function stopOpPolling() {
  if (state.op) clearTimeout(state.op.timer);
  state.op = null;
}

function pollOperation(id, first) {
  stopOpPolling();
  const sessionId = state.session.id;
  state.op = { id, sessionId, timer: null, meta: null };
  delete $('progress-text').dataset.outcome;
  renderSessionHeader();
  const tick = async (op) => {
    if (!state.op || state.op.id !== id || state.session?.id !== sessionId) return;
    try {
      op = op || (await api.operation(id));
    } catch (e) {
      showError($('session-error'), e);
      stopOpPolling();
      renderSessionHeader();
      return;
    }
    const m = op.metadata || {};
    if (op.done) {
      stopOpPolling();
      const cancelled = op.error && isCancelled(op.error);
      if (op.error && !cancelled) showError($('session-error'), new ApiError(op.error.status || 500, op.error));
      await refreshSession();
      renderProgress(m);
      if (cancelled) $('progress-text').textContent += ' · cancelled';
      $('progress-text').dataset.outcome = cancelled ? 'cancelled' : op.error ? 'failed' : 'done';
      startStream(); /* catch up on rows stored after the stream last closed */
      refreshSessions();
      return;
    }
    state.op.meta = m;
    if (typeof m.t === 'number') Object.assign(state.session, { status: 'running', t: Math.max(m.t, state.session.t || 0) });
    renderSessionHeader();
    state.op.timer = setTimeout(() => tick(), 300);
  };
  tick(first); /* POST run answers with the operation itself */
}

async function onCancel() {
  if (!state.op) return;
  try {
    await api.cancel(state.op.id);
  } catch (e) {
    showError($('session-error'), e);
  }
}

async function onDelete() {
  const s = state.session;
  if (!s || !confirm(`Delete session ${s.id}?`)) return;
  try {
    await api.deleteSession(s.id);
  } catch (e) {
    if (e.status !== 404) {
      showError($('session-error'), e);
      return;
    }
  }
  closeSession(`Session ${s.id} was deleted.`);
  refreshSessions();
}

/* No session open any more (`notice` says why): every panel drops its data. */
function closeSession(notice) {
  const id = state.session?.id;
  state.stream?.stop();
  state.stream = null;
  stopOpPolling();
  state.session = null;
  state.store = null;
  state.picks = [];
  plots.stop();
  frames.clear();
  fft.clear();
  if (compare.shows(id)) compare.clear();
  for (const box of ['session-error', 'fft-error']) hideError($(box));
  $('plots-empty').hidden = false;
  $('channel-list').replaceChildren();
  $('unit-toggles').replaceChildren();
  $('fft-channel').replaceChildren();
  $('fft-btn').disabled = true;
  $('stream-status').textContent = 'no stream';
  $('stream-status').className = 'pill muted';
  for (const tr of $('session-table').querySelectorAll('tr.selected')) tr.classList.remove('selected');
  renderSessionHeader(notice);
  updateSampleCount();
}

/* ---------- channels and units ---------- */

function renderChannelPicker() {
  const box = $('channel-list');
  box.replaceChildren();
  for (const c of channelsOf(state.session)) {
    const lab = document.createElement('label');
    lab.className = 'chip';
    lab.title = c.description || '';
    const cb = document.createElement('input');
    cb.type = 'checkbox';
    cb.value = c.name;
    cb.checked = state.picks.includes(c.name);
    cb.addEventListener('change', () => {
      state.picks = [...box.querySelectorAll('input:checked')].map((x) => x.value);
      plots.show(state.store, state.picks);
    });
    lab.append(cb, ` ${c.name} `);
    const u = document.createElement('span');
    u.className = 'unit';
    u.textContent = bracket(display(c.unit).label);
    lab.append(u);
    box.append(lab);
  }
}

function renderUnitToggles() {
  const box = $('unit-toggles');
  box.replaceChildren();
  const units = [...new Set(channelsOf(state.session).map((c) => c.unit))];
  for (const u of units) {
    const list = choices(u);
    if (list.length < 2) continue;
    const group = document.createElement('span');
    group.className = 'seg';
    group.dataset.unit = u;
    const cap = document.createElement('span');
    cap.className = 'muted';
    cap.textContent = { 'm/s': 'speed', 'rad/s': 'rotation', rad: 'angle', W: 'power', Pa: 'pressure' }[u] || u;
    group.append(cap);
    for (const c of list) {
      const b = document.createElement('button');
      b.type = 'button';
      b.className = `small seg-btn${display(u).label === c.label ? ' on' : ''}`;
      b.textContent = c.label;
      b.addEventListener('click', () => {
        setDisplay(u, c.label);
        renderUnitToggles();
        renderChannelPicker();
        relabelChannelSelect($('fft-channel'));
        relabelChannelSelect($('compare-channel'));
        plots.show(state.store, state.picks);
      });
      group.append(b);
    }
    box.append(group);
  }
}

/* ---------- compare ---------- */

function updateCompareInfo() {
  const n = state.compare.size;
  $('compare-info').textContent = n ? `${n} session${n > 1 ? 's' : ''} ticked` : 'none ticked';
}

async function onCompare() {
  const box = $('compare-error');
  hideError(box);
  if (state.compare.size < 1) {
    showError(box, new ApiError(0, { title: 'Nothing to compare', detail: 'tick sessions in the list (cmp column) first' }));
    return;
  }
  try {
    const sessions = await Promise.all([...state.compare].map((id) => api.session(id)));
    const chans = [];
    for (const s of sessions) for (const c of channelsOf(s)) if (!chans.some((x) => x.name === c.name)) chans.push(c);
    const sel = $('compare-channel');
    if (!chans.some((c) => c.name === sel.value)) fillChannelSelect(sel, chans, state.picks[0]);
    const r = await compare.show(sessions, sel.value);
    const lacking = r.missing.map((s) => String(s.id).slice(0, 8)).join(', ');
    $('compare-info').textContent = `${r.series} session${r.series > 1 ? 's' : ''} overlaid${lacking ? ` · not plotted, no channel ${sel.value}: ${lacking}` : ''}`;
  } catch (e) {
    compare.clear(); /* an overlay of an earlier request would pass for this one */
    showError(box, e);
  }
}

async function updateCompareChannels() {
  if ($('compare-channel').options.length) return;
  const chans = state.session ? channelsOf(state.session) : [];
  fillChannelSelect($('compare-channel'), chans, state.picks[0]);
}

/* ---------- FFT ---------- */

async function onFft() {
  const box = $('fft-error');
  hideError(box);
  const fields = { from: 'fft-from', to: 'fft-to', 'show up to': 'fft-fmax' };
  const v = {};
  const errors = [];
  for (const [name, id] of Object.entries(fields)) {
    const r = readNumber($(id), { name, min: 0, optional: true });
    markInput($(id), null, r.error);
    if (r.error) errors.push(r.error);
    v[name] = r.value;
  }
  try {
    if (errors.length) throw new ApiError(0, { title: 'Not computed', detail: errors.join('; ') });
    await fft.compute(state.session, $('fft-channel').value, v.from, v.to, { fmax: v['show up to'], log: $('fft-log').checked });
  } catch (e) {
    fft.clear(); /* the last spectrum is not the answer to this request */
    showError(box, e);
  }
}

/* ---------- boot ---------- */

const plots = new LivePlots($('plots'));
const fft = new FftPanel($('fft-plot'));
const compare = new ComparePanel($('compare-plot'));
const frames = new FrameViewer({
  img: $('frame-img'),
  placeholder: $('frame-placeholder'),
  scrub: $('scrub'),
  time: $('frame-time'),
  play: $('play-btn'),
  view: $('frame-view'),
  exaggeration: $('frame-exag'),
  exaggerationError: $('frame-exag-error'),
  tension: $('frame-tension'),
  status: $('frame-status'),
});

async function boot() {
  try {
    const h = await api.health();
    $('health').textContent = `tanksimd ${h.version || ''} · ${h.status || 'ok'}`;
    $('health').className = 'health ok';
  } catch (e) {
    $('health').textContent = `daemon unreachable: ${e.message}`;
    $('health').className = 'health bad';
  }
  try {
    await initCreateForm();
    hideError($('create-error'));
  } catch (e) {
    showError($('create-error'), e);
  }
  await refreshSessions();
}

/* Read-only handle for the browser test (tests/web/dashboard.test.mjs). */
window.tanksimDebug = { state, plots, compare, fft };

initToken();
$('create-form').addEventListener('submit', onCreate);
$('refresh-sessions').addEventListener('click', refreshSessions);
$('step-btn').addEventListener('click', onStep);
$('run-btn').addEventListener('click', onRun);
$('cancel-btn').addEventListener('click', onCancel);
$('delete-session').addEventListener('click', onDelete);
$('fft-btn').addEventListener('click', onFft);
/* an edited number field loses its error mark until it is used again */
for (const id of ['step-duration', 'fft-from', 'fft-to', 'fft-fmax']) $(id).addEventListener('input', () => markInput($(id), null, ''));
$('compare-btn').addEventListener('click', onCompare);
$('compare-channel').addEventListener('focus', updateCompareChannels);
setInterval(() => {
  updateSampleCount();
  if (state.session) frames.updateRange(state.store?.length ? state.store.t[state.store.length - 1] : state.session.t || 0);
}, 300);
setInterval(() => {
  if (!document.hidden) refreshSessions();
}, 3000);
boot();
