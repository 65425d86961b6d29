/**
 * Calls to the UniPhys API with the stored key. Failures throw {@link ApiError} carrying the
 * API's `{"error":{"code","message"}}`; a 401 also forgets the key and tells the app, which
 * shows the sign-in form.
 */

const KEY_STORAGE = 'uniphys.apiKey';

/** The API key kept in localStorage. */
export const apiKey = {
  get: () => localStorage.getItem(KEY_STORAGE),
  set: (key) => localStorage.setItem(KEY_STORAGE, key),
  clear: () => localStorage.removeItem(KEY_STORAGE),
};

/** A failed call: HTTP `status` (0 when the server could not be reached), API `code`, `message`. */
export class ApiError extends Error {
  constructor(status, code, message) {
    super(message);
    this.name = 'ApiError';
    this.status = status;
    this.code = code;
  }
}

let onUnauthorized = () => {};

/** Sets what happens after a 401 (the key is already forgotten): `handler(message)`. */
export function setUnauthorizedHandler(handler) {
  onUnauthorized = handler;
}

/** `?a=1&b=2` of the given parameters, leaving out null, undefined and empty ones. */
export function query(params) {
  const search = new URLSearchParams();
  for (const [name, value] of Object.entries(params)) {
    if (value !== null && value !== undefined && value !== '') search.set(name, String(value));
  }
  const text = search.toString();
  return text ? `?${text}` : '';
}

/**
 * Fetches `path` (`/v1/...`) with the key; answers the Response of a 2xx, throws ApiError
 * otherwise. An abort (through `signal`) throws the DOMException `AbortError` untouched.
 */
export async function request(path, { method = 'GET', body, signal, headers = {} } = {}) {
  const key = apiKey.get();
  const all = { ...headers };
  if (key) all.Authorization = `Bearer ${key}`;
  let response;
  try {
    response = await fetch(path, { method, body, signal, headers: all });
  } catch (e) {
    if (e.name === 'AbortError') throw e;
    throw new ApiError(0, 'unreachable', `cannot reach the server (${e.message})`);
  }
  if (response.ok) return response;
  const error = await errorOf(response);
  // Only the first of several concurrent 401s (the key they used is still the stored one)
  // signs out; the others would replace its message with that of an aborted read.
  if (response.status === 401 && key && apiKey.get() === key) {
    apiKey.clear();
    onUnauthorized(error.message);
  }
  throw error;
}

/** GET `path` and parse its JSON. */
export async function getJson(path, options) {
  return (await request(path, options)).json();
}

/** POST `path` (no body) and parse the JSON answer. */
export async function postJson(path, options = {}) {
  return (await request(path, { ...options, method: 'POST' })).json();
}

/** GET `path` as text (artifact downloads: OBJ, JSON files). */
export async function getText(path, options) {
  return (await request(path, options)).text();
}

/** GET `path` as a Blob (downloads that need the auth header). */
export async function getBlob(path, options) {
  return (await request(path, options)).blob();
}

async function errorOf(response) {
  const text = await response.text().catch(() => '');
  try {
    const { error } = JSON.parse(text);
    if (error?.message) return new ApiError(response.status, error.code ?? '', error.message);
  } catch {
    // Not the API's JSON error (a proxy's page, say): fall through to the status line.
  }
  const detail = text.trim().slice(0, 200) || response.statusText;
  return new ApiError(response.status, 'http', `HTTP ${response.status}: ${detail}`);
}
