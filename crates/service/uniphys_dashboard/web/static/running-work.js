/**
 * The overview's running work (`#running-table`): one row per unfinished stage of the newest
 * running jobs, with its worker, time running and progress.
 */

import { h, syncRows, table } from './dom.js';
import { count, percent } from './format.js';

/** A table of `GET /v1/work?state=running` items. */
export function runningTable() {
  return table({ id: 'running-table', class: 'data' }, 'Running work (newest jobs first)',
    ['Job', 'Asset', 'Stage', 'State', 'Attempt', 'Worker', 'Running for', 'Progress']);
}

/** Shows `items` in a table made by {@link runningTable}. */
export function updateRunningTable(element, items, nowMs = Date.now()) {
  syncRows(element.tBodies[0], items.map((item) => ({ ...item, shown: stateOf(item, nowMs) })), {
    keyOf: (item) => `${item.job_id}/${item.stage}`,
    empty: 'Nothing is running.',
    rowProps: (item) => ({ dataset: { job: item.job_id, stage: item.stage } }),
    cells: (item) => [
      h('td', {}, h('a', { href: `#/assets/${encodeURIComponent(item.asset_id)}`, text: item.job_id })),
      h('td', {}, h('a', { href: `#/assets/${encodeURIComponent(item.asset_id)}`, text: item.file_name ?? item.asset_id })),
      h('td', { text: item.stage }),
      h('td', {}, h('span', { class: `badge state-${item.state}`, text: item.shown }),
        item.errors ? h('span', { class: 'muted', text: ` ${item.errors} failed` }) : null),
      h('td', { class: 'num', text: `${count(item.attempt)} / ${count(item.max_attempts)}` }),
      h('td', { text: item.worker_id ?? '—' }),
      h('td', { class: 'num' },
        item.state === 'running' && item.started_at_ms ? h('span', { 'data-since-ms': item.started_at_ms }) : '—'),
      h('td', {}, progressOf(item)),
    ],
  });
}

/** The stage's state, telling a run waiting out a retry backoff from one ready now. */
function stateOf(item, nowMs) {
  if (item.state === 'ready' && item.run_after_ms > nowMs) return 'backing off';
  return item.state;
}

function progressOf(item) {
  const p = item.progress;
  if (!p) return '—';
  return h('div', { class: 'progress' },
    h('progress', { max: 1, value: p.fraction, 'aria-label': `${item.stage} progress` }),
    h('span', { text: ` ${percent(p.fraction)} ${p.message ?? ''}` }));
}
