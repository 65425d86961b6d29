/**
 * The sign-in form (`#login-view` in index.html): asks for the API key, which is kept in
 * localStorage. It is not checked here: the first call that answers 401 brings the form back
 * with the server's message.
 */

import { apiKey } from './api.js';

const view = () => document.getElementById('login-view');

/** Shows the form, with `message` (an error, or why it is shown) when given. */
export function showLogin(message = '') {
  const error = document.getElementById('login-error');
  error.textContent = message;
  error.hidden = !message;
  view().hidden = false;
  document.getElementById('sign-out').hidden = true;
  document.getElementById('api-key').focus();
}

/** Hides the form. */
export function hideLogin() {
  view().hidden = true;
  document.getElementById('sign-out').hidden = false;
}

/** Calls `onSignedIn()` each time a key is submitted, after storing it. */
export function onLogin(onSignedIn) {
  document.getElementById('login-form').addEventListener('submit', (event) => {
    event.preventDefault();
    const input = document.getElementById('api-key');
    const key = input.value.trim();
    if (!key) return;
    apiKey.set(key);
    input.value = '';
    onSignedIn();
  });
}
