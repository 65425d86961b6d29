/**
 * The asset page's stage table (`#stage-runs`): each stage of the latest job with its state,
 * attempts, timing, failed attempts and, while running, a progress bar.
 */

import { h, syncRows, table } from './dom.js';
import { count, duration, percent, time } from './format.js';

/** An empty `#stage-runs` table. */
export function stageRunsTable() {
  return table({ id: 'stage-runs', class: 'data' }, 'Stages of the latest job',
    ['Stage', 'State', 'Attempts', 'Started', 'Duration', 'Errors', 'Progress', 'Worker']);
}

/** Shows `job.stages` (in the job's topological order). */
export function updateStageRuns(element, job) {
  syncRows(element.tBodies[0], job?.stages ?? [], {
    keyOf: (s) => s.name,
    empty: 'No job.',
    rowProps: (s) => ({ dataset: { stage: s.name, state: s.state } }),
    cells: (s) => [
      h('th', { scope: 'row', text: s.name }),
      h('td', {}, h('span', { class: `badge state-${s.state}`, text: s.state })),
      h('td', { class: 'num', text: `${count(s.attempt)} / ${count(s.max_attempts)}` }),
      h('td', { text: time(s.started_at_ms) }),
      h('td', { class: 'num' }, durationOf(s)),
      h('td', { class: 'errors' }, errorsOf(s.errors ?? [])),
      h('td', {}, progressOf(s)),
      h('td', { text: s.worker_id ?? '—' }),
    ],
  });
}

function durationOf(stage) {
  if (stage.duration_ms !== null && stage.duration_ms !== undefined) return duration(stage.duration_ms);
  if (stage.state === 'running' && stage.started_at_ms) return h('span', { 'data-since-ms': stage.started_at_ms });
  return '—';
}

/** The failed attempts, the last one shown and all of them behind a disclosure. */
function errorsOf(errors) {
  if (errors.length === 0) return '0';
  const line = (e) => [h('span', { class: `badge kind-${e.kind}`, text: e.kind }), ' ',
    `attempt ${e.attempt}: `, h('span', { class: 'error-message', text: e.message })];
  const last = errors[errors.length - 1];
  return h('details', {},
    h('summary', {}, `${errors.length} failed: `, ...line(last)),
    h('ol', {}, errors.map((e) => h('li', {}, ...line(e), h('span', { class: 'muted', text: ` (${time(e.at_ms)}, ${e.worker_id ?? 'no worker'})` })))));
}

function progressOf(stage) {
  if (stage.state !== 'running') return stage.state === 'succeeded' ? 'done' : '—';
  const p = stage.progress;
  const bar = p && typeof p.fraction === 'number'
    ? h('progress', { max: 1, value: p.fraction, 'aria-label': `${stage.name} progress` })
    : h('progress', { 'aria-label': `${stage.name} progress` });
  return h('div', { class: 'progress' }, bar,
    h('span', { text: p ? ` ${percent(p.fraction)} ${p.message ?? ''}` : ' running' }));
}
