/*
 * messages.js — telling the user what went wrong: a panel's error box (an
 * ApiError's title, and its errors[] by JSON pointer), the banner at the
 * top, and the API token form that a 401 points to (askForToken).
 */
import { ApiError, getToken, setToken } from './api.js';
import { $ } from './dom.js';

export function showError(box, err) {
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
  if (e.status === 401) askForToken();
}

/* What the API's status `interrupted` means (api/openapi.yaml), for a session without an `error` of its own. */
const INTERRUPTED = 'the daemon stopped during its run (crash or shutdown); Run to end continues it from the last stored state';

/* A session's own error (the daemon's reason) in `box`, what an interrupted run means
 * when it has none, or an empty box. */
export function showSessionError(box, s) {
  const why = s?.error || (s?.status === 'interrupted' ? INTERRUPTED : '');
  if (why) showError(box, new ApiError(0, { title: `Session ${s.status}`, detail: why }));
  else hideError(box);
}

export const hideError = (box) => {
  box.hidden = true;
  box.replaceChildren();
};

function banner(text) {
  const b = $('banner');
  b.textContent = text || '';
  b.hidden = !text;
}

/* A 401: the banner says whether the token is missing or was rejected, and the token input asks for it.
 * Only the first 401 (until Save) takes the keyboard focus: the list's poll meets one every 3 s. */
export function askForToken() {
  banner(getToken() ? 'The daemon rejected the saved API token: enter the right one at the top right and press Save.' : 'The daemon requires an API token: enter it at the top right and press Save.');
  const input = $('token-input');
  if (input.classList.contains('attention')) return;
  input.classList.add('attention');
  input.focus();
}

/* The token form: Save keeps the token (api.js) and calls onSaved to load everything again. */
export function initTokenForm(onSaved) {
  $('token-input').value = getToken();
  $('token-form').addEventListener('submit', (ev) => {
    ev.preventDefault();
    setToken($('token-input').value.trim());
    banner('');
    $('token-input').classList.remove('attention');
    onSaved();
  });
}
