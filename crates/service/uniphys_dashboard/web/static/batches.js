/**
 * The batch list (`#/batches`): each batch label with its job count, newest first, one keyset
 * page at a time.
 */

import { getJson, query } from './api.js';
import { h, syncRows, table } from './dom.js';
import { count, time } from './format.js';
import { Pager } from './pager.js';

const PAGE_SIZE = 50;

export function mount(root) {
  const controller = new AbortController();
  const list = table({ id: 'batches', class: 'data' }, 'Batches (newest first)', ['Batch', 'Jobs', 'Created']);
  const message = h('p', { class: 'banner error', role: 'alert', hidden: true });
  const pager = new Pager(() => load().then(() => window.scrollTo({ top: 0 })));

  root.append(h('section', { id: 'batch-list', class: 'page' },
    h('h1', { text: 'Batches' }),
    h('p', { class: 'muted', text: 'Assets submitted with the same batch label, for dataset statistics.' }),
    message,
    h('div', { class: 'scroll' }, list),
    pager.element));

  async function load() {
    try {
      const page = await getJson(`/v1/batches${query({ before: pager.before, limit: PAGE_SIZE })}`,
        { signal: controller.signal });
      message.hidden = true;
      syncRows(list.tBodies[0], page.items, {
        keyOf: (b) => b.batch,
        empty: 'No batches yet: submit assets with ?batch=<label> to group them.',
        rowProps: (b) => ({ dataset: { batch: b.batch } }),
        cells: (b) => [
          h('th', { scope: 'row' }, h('a', { href: `#/batches/${encodeURIComponent(b.batch)}`, text: b.batch })),
          h('td', { class: 'num', text: count(b.jobs) }),
          h('td', { text: time(b.created_at_ms) }),
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
