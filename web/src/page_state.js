/*
 * page_state.js — what a reload keeps, in location.hash: the open session
 * ("#session=ID") and the run pace ("&pace=5"). Written with
 * history.replaceState (no history entry, no hashchange), read once in boot.
 */

/* {session, pace} from the hash ('' or undefined when absent). */
export function readPageState() {
  const p = new URLSearchParams(location.hash.replace(/^#/, ''));
  return { session: p.get('session') || '', pace: p.get('pace') || '' };
}

/* Change the fields of `patch` ({session, pace}: '' or null removes one) in the hash. */
export function writePageState(patch) {
  const p = new URLSearchParams(location.hash.replace(/^#/, ''));
  for (const [k, v] of Object.entries(patch)) {
    if (v) p.set(k, v);
    else p.delete(k);
  }
  const hash = p.toString();
  history.replaceState(history.state, '', `${location.pathname}${location.search}${hash ? `#${hash}` : ''}`);
}
