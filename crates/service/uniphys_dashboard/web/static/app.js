/**
 * The dashboard's entry point: hash routes to pages, the sign-in gate and sign-out.
 *
 * A page module exports `mount(root, params)`, which fills `root` and answers a function that
 * stops its timers and frees what it holds; it is called before the next page mounts.
 */

import { apiKey, setUnauthorizedHandler } from './api.js';
import { h } from './dom.js';
import { hideLogin, onLogin, showLogin } from './login.js';
import * as overview from './overview.js';
import * as assets from './assets.js';
import * as asset from './asset.js';
import * as batches from './batches.js';
import * as batch from './batch.js';

/** Route patterns over the hash's path (`#/assets/asset_7` → `/assets/asset_7`). */
const ROUTES = [
  { pattern: /^\/?$/, page: overview, nav: 'overview' },
  { pattern: /^\/assets\/?$/, page: assets, nav: 'assets' },
  { pattern: /^\/assets\/([^/]+)$/, page: asset, nav: 'assets', names: ['id'] },
  { pattern: /^\/batches\/?$/, page: batches, nav: 'batches' },
  { pattern: /^\/batches\/([^/]+)$/, page: batch, nav: 'batches', names: ['label'] },
];

const app = document.getElementById('app');
let unmount = null;

/** `#/assets?state=dead` → `{path: '/assets', query: URLSearchParams('state=dead')}`. */
function parseHash(hash) {
  const text = hash.replace(/^#/, '');
  const at = text.indexOf('?');
  return at < 0
    ? { path: text, query: new URLSearchParams() }
    : { path: text.slice(0, at), query: new URLSearchParams(text.slice(at + 1)) };
}

function leavePage() {
  unmount?.();
  unmount = null;
  app.replaceChildren();
}

/** Mounts the page of the current hash, or the sign-in form when there is no key. */
function render() {
  leavePage();
  if (!apiKey.get()) {
    showLogin();
    return;
  }
  hideLogin();
  const { path, query } = parseHash(location.hash);
  for (const route of ROUTES) {
    const match = route.pattern.exec(path);
    if (!match) continue;
    const params = { query };
    try {
      (route.names ?? []).forEach((name, i) => {
        params[name] = decodeURIComponent(match[i + 1]);
      });
    } catch {
      break; // A malformed escape (`%E0`): no page has that name.
    }
    markNav(route.nav);
    unmount = route.page.mount(app, params);
    return;
  }
  markNav(null);
  app.append(h('section', { class: 'page' }, h('h1', { text: 'Not found' }),
    h('p', {}, 'No page at ', h('code', { text: location.hash }), '. ', h('a', { href: '#/', text: 'Overview' }))));
}

function markNav(current) {
  for (const link of document.querySelectorAll('nav.main a[data-nav]')) {
    if (link.dataset.nav === current) link.setAttribute('aria-current', 'page');
    else link.removeAttribute('aria-current');
  }
}

setUnauthorizedHandler((message) => {
  leavePage();
  showLogin(message);
});

onLogin(render);

document.getElementById('sign-out').addEventListener('click', () => {
  apiKey.clear();
  leavePage();
  showLogin();
});

window.addEventListener('hashchange', render);
render();
