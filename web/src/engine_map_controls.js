/*
 * engine_map_controls.js — the Analyses panel's engine-map form: an
 * engine-map preset (the variant: GET /v1/presets' engine_dyno scenarios,
 * setPresets) and the engine fidelity, sent as a run
 * config to POST /v1/engine-map; the operation is followed by analysis_op.js
 * and its map drawn by EngineMapPanel (engine_map.js); changed, showStored,
 * attach, reset, shown: see analysis_op.js. Showing a stored map puts the
 * preset and fidelity it was asked with back in the form (its operation's
 * metadata.request; a fidelity the body left to the preset: the map's own),
 * or the form said other inputs than those of the map shown (review).
 */
import { api } from './api.js';
import { $, presetOptions, selectIf } from './dom.js';
import { initAnalysisOp } from './analysis_op.js';

export function initEngineMapControls(state, engineMap, { changed }) {
  const op = initAnalysisOp(state, 'engine_map', 'map', { onDone: (doc) => engineMap.draw(doc), onClear: () => engineMap.clear(), changed });

  function onRun() {
    const doc = { preset: $('map-preset').value, engine: { fidelity: $('map-fidelity').value } };
    op.start(() => api.engineMap(doc));
  }

  /* The form's inputs as stored operation `stored` asked (an input the form has no option for is left). */
  function restore(stored) {
    const body = stored.metadata?.request?.body || {};
    selectIf($('map-preset'), body.preset);
    selectIf($('map-fidelity'), body.engine?.fidelity ?? stored.response?.fidelity);
  }

  $('map-run').addEventListener('click', onRun);
  /* presets: GET /v1/presets' list; the engine-on-dynamometer ones are the engine variants */
  return {
    setPresets: (presets) => {
      presetOptions($('map-preset'), presets.filter((p) => p.kind === 'engine_dyno'));
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
