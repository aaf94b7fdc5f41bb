/*
 * main.js — the tanksim dashboard's entry point: builds the chart panels and
 * the one `state` object, hands them to each part, and boots.
 *
 * Parts: messages (error boxes, banner, token), session_list (polled),
 * create_form (from /v1/schema), session_view (open / close / delete),
 * session_header (header, progress), run_controls (step, run, cancel,
 * operation polling), session_stream (live rows), channels (chips, unit
 * toggles), fft_controls and compare_controls (their panels' forms),
 * engine_map_controls and tune_controls (the Analyses panel's forms),
 * stored_analyses (its list of stored analyses, told by the forms),
 * page_state (the open session and the pace, kept across a reload).
 */
import 'uplot/dist/uPlot.min.css';
import './style.css';
import { api } from './api.js';
import { $ } from './dom.js';
import { LivePlots } from './plots.js';
import { FftPanel } from './fft.js';
import { FrameViewer } from './frames.js';
import { ComparePanel } from './compare.js';
import { EngineMapPanel } from './engine_map.js';
import { hideError, initTokenForm, showError } from './messages.js';
import { initSessionHeader } from './session_header.js';
import { initSessionStream } from './session_stream.js';
import { initChannelPicker } from './channels.js';
import { initFftControls } from './fft_controls.js';
import { initRunFigures } from './run_figures.js';
import { initCompareControls } from './compare_controls.js';
import { initRunControls } from './run_controls.js';
import { initSessionView } from './session_view.js';
import { initSessionList } from './session_list.js';
import { initCreateForm } from './create_form.js';
import { initEngineMapControls } from './engine_map_controls.js';
import { initTuneControls } from './tune_controls.js';
import { initStoredAnalyses } from './stored_analyses.js';
import { drawnTickLabels } from './ticks.js';
import { followLimits } from './operation.js';
import { readPageState, writePageState } from './page_state.js';
import { setDisplay, fmtTime } from './units.js';

const state = {
  compare: new Set(), /* ids ticked for Compare */
  session: null, /* the open session object */
  store: null, /* its samples (SeriesStore) */
  stream: null, /* its SSE stream, while one is open */
  picks: [], /* the channels charted */
  op: null, /* {id, sessionId, meta, follower} of the run operation being followed */
  analyses: { engine_map: null, tune: null }, /* {id, follower} of each analysis operation being followed */
  schema: null, /* GET /v1/schema, once loaded (field ranges) */
};

/* after each redraw the sample counter and the header's t follow the rows drawn (plots.js) */
const plots = new LivePlots($('plots'), { onDraw: (drawn) => rowsDrawn(drawn) });
const fft = new FftPanel($('fft-plot'));
const compare = new ComparePanel($('compare-plot'));
const engineMap = new EngineMapPanel($('map-plot'), $('map-summary'));
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

/* Handle for the browser test (tests/web/dashboard.test.mjs; compareCached is added below): read-only, but for setUnit (units.js setDisplay)
 * and followLimits (operation.js: the test shortens how long a follower waits for an unreachable daemon). */
window.tanksimDebug = { state, plots, compare, fft, engineMap, tickLabels: drawnTickLabels, setUnit: setDisplay, followLimits, fmtTime };

initTokenForm(boot);
const refreshList = () => list.refresh(); /* list is made last: it shows the open session */
const header = initSessionHeader(state);
const stream = initSessionStream(state, plots);
function rowsDrawn(drawn) {
  if (drawn.store !== state.store) return; /* a store the open session no longer has */
  stream.updateCount();
  header.rowsDrawn(drawn.t);
}
const picker = initChannelPicker(state, plots);
const fftControls = initFftControls(state, fft);
const compareControls = initCompareControls(state, compare);
window.tanksimDebug.compareCached = compareControls.cached;
const run = initRunControls(state, { header, stream, refreshList });
const figures = initRunFigures(state);
const view = initSessionView(state, { plots, frames, header, stream, picker, fftControls, compareControls, figures, run, refreshList });
const list = initSessionList(state, { view, ticksChanged: compareControls.updateInfo });
const form = initCreateForm({ refreshList, open: view.open });
/* a stored analysis is shown by the form of its kind (the forms are made next) */
const stored = initStoredAnalyses({ form: (kind) => ({ engine_map: mapControls, tune: tuneControls })[kind] });
const mapControls = initEngineMapControls(state, engineMap, { changed: stored.changed });
const tuneControls = initTuneControls(state, { changed: stored.changed });

/* The health pill follows the daemon: asked again every HEALTH_MS while the
 * page is visible (it said "ok" all the while a stopped daemon was away). */
const HEALTH_MS = 5000;
async function checkHealth() {
  if (document.hidden) return;
  try {
    const h = await api.health();
    $('health').textContent = `tanksimd ${h.version || ''} · ${h.status || 'ok'}`;
    $('health').className = 'health ok';
  } catch (e) {
    /* a draining daemon answers 503 with its status: say that rather than "unreachable" */
    const stopping = e.status === 503;
    $('health').textContent = stopping ? `tanksimd stopping: ${e.message}` : `daemon unreachable: ${e.message}`;
    $('health').className = 'health bad';
  }
}

async function boot() {
  await checkHealth();
  try {
    /* the analyses' preset lists do not wait for the schema: it may fail on its own */
    const presets = (await api.presets()).presets || [];
    mapControls.setPresets(presets);
    tuneControls.setPresets(presets);
    state.schema = await form.load(presets);
    hideError($('create-error'));
  } catch (e) {
    showError($('create-error'), e);
  }
  await Promise.all([list.refresh(), stored.refresh({ attach: true })]);
  await reopen();
}

/* The session open before a reload (page_state.js), if it still exists and none is open. */
async function reopen() {
  const { session: id } = readPageState();
  if (!id || state.session) return;
  let s;
  try {
    s = await api.session(id);
  } catch (e) {
    if (e.status === 404) writePageState({ session: null }); /* deleted meanwhile */
    return;
  }
  if (!state.session) await view.open(id, s);
}

/* The run pace survives a reload too. */
const pace = readPageState().pace;
if ([...$('run-pace').options].some((o) => o.value === pace)) $('run-pace').value = pace;
$('run-pace').addEventListener('change', () => writePageState({ pace: $('run-pace').value }));

/* the sample count and the frame scrubber's range follow the stored rows (close() resets them) */
setInterval(() => {
  if (!state.session) return;
  stream.updateCount();
  fftControls.update();
  figures.update();
  frames.updateRange(state.store?.length ? state.store.t[state.store.length - 1] : state.session.t || 0);
}, 300);
setInterval(() => {
  if (!document.hidden) list.refresh();
}, 3000);
/* one poll however often boot runs (a token Save boots again) */
setInterval(checkHealth, HEALTH_MS);
boot();
