/**
 * The asset list (`#/assets?state=running|succeeded|dead|cancelled`): newest jobs first, one
 * keyset page of {@link PAGE_SIZE} at a time.
 */

import { getJson, query } from './api.js';
import { h, syncRows, table } from './dom.js';
import { time } from './format.js';
import { Pager } from './pager.js';

const PAGE_SIZE = 50;
const STATES = ['running', 'succeeded', 'dead', 'cancelled'];

export function mount(root, { query: params }) {
  const state = params.get('state') || null;
  const controller = new AbortController();
  const list = table({ id: 'assets-table', class: 'data' }, state ? `Jobs in state ${state}, newest first` : 'Jobs, newest first',
    ['Asset', 'File', 'Job', 'State', 'Priority', 'Submitted', 'Finished']);
  const message = h('p', { class: 'banner error', role: 'alert', hidden: true });
  const pager = new Pager(() => load().then(() => window.scrollTo({ top: 0 })));

  root.append(h('section', { id: 'assets', class: 'page' },
    h('h1', { text: 'Assets' }),
    h('nav', { class: 'filters', 'aria-label': 'Filter by job state' },
      [null, ...STATES].map((s) => h('a', {
        href: s ? `#/assets?state=${s}` : '#/assets',
        'aria-current': s === state ? 'page' : null,
        text: s ?? 'all',
      }))),
    message,
    h('div', { class: 'scroll' }, list),
    pager.element));

  async function load() {
    try {
      const page = await getJson(`/v1/assets${query({ state, before: pager.before, limit: PAGE_SIZE })}`,
        { signal: controller.signal });
      message.hidden = true;
      syncRows(list.tBodies[0], page.items, {
        keyOf: (a) => a.job_id,
        empty: state ? `No job is ${state}.` : 'No assets yet.',
        rowProps: (a) => ({ dataset: { asset: a.asset_id } }),
        cells: (a) => [
          h('td', {}, h('a', { href: `#/assets/${encodeURIComponent(a.asset_id)}`, text: a.asset_id })),
          h('td', { text: a.file_name ?? '—' }),
          h('td', { text: a.job_id ?? '—' }),
          h('td', {}, h('span', { class: `badge state-${a.state}`, text: a.state ?? '—' })),
          h('td', { class: 'num', text: a.priority ?? '—' }),
          h('td', { text: time(a.created_at_ms) }),
          h('td', { text: time(a.finished_at_ms) }),
        ],
      });
      pager.loaded(page.next);
    } catch (e) {
      if (e.name === 'AbortError') return;
      message.textContent = e.message;
      message.hidden = false;
      pager.loaded(pager.next);
    }
  }

  load();
  return () => controller.abort();
}
