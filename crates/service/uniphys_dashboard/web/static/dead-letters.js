/**
 * The overview's dead letters (`#dead-table`): one row per dead job with the stage that died, its
 * last error and a Retry button. A retry's answer ("requeued: ingest", or the error) stays in the
 * row for as long as the page is open, even while the retried job is running again and so is
 * no longer listed as dead.
 */

import { postJson } from './api.js';
import { h, syncRows, table } from './dom.js';
import { count, time } from './format.js';

export class DeadLetters {
  /** @param {() => void} onRetried called after each retry answer (to refresh the page). */
  constructor(onRetried) {
    this.onRetried = onRetried;
    /** job id → `{pending, text, group}` of the retries made on this page. */
    this.retries = new Map();
    this.groups = [];
    this.element = table({ id: 'dead-table', class: 'data' }, 'Dead letters (newest first)',
      ['Job', 'Asset', 'Stage', 'Error', 'Attempts', 'Failed at', 'Action']);
  }

  /** Shows the items of `GET /v1/work?state=dead`. */
  update(items) {
    this.groups = groupByJob(items);
    this.render();
  }

  render() {
    const listed = new Set(this.groups.map((g) => g.job_id));
    const rows = this.groups.map((g) => ({ ...g, dead: true }));
    for (const [jobId, retry] of this.retries) {
      if (!listed.has(jobId)) rows.push({ ...retry.group, dead: false });
    }
    const withRetry = rows.map((row) => {
      const retry = this.retries.get(row.job_id);
      return { ...row, retry: retry ? { pending: retry.pending, text: retry.text } : null };
    });
    syncRows(this.element.tBodies[0], withRetry, {
      keyOf: (row) => row.job_id,
      empty: 'No dead letters.',
      rowProps: (row) => ({ dataset: { job: row.job_id }, class: row.dead ? null : 'retried' }),
      cells: (row) => this.cells(row),
    });
  }

  cells(row) {
    const error = row.last_error;
    const button = h('button', {
      type: 'button', class: 'retry', 'data-job': row.job_id, text: 'Retry',
      disabled: !row.dead || Boolean(row.retry?.pending),
      onclick: () => this.retry(row),
    });
    return [
      h('td', {}, h('a', { href: `#/assets/${encodeURIComponent(row.asset_id)}`, text: row.job_id })),
      h('td', {}, h('a', { href: `#/assets/${encodeURIComponent(row.asset_id)}`, text: row.file_name ?? row.asset_id })),
      h('td', { class: 'stage' }, row.stages.join(', '),
        row.blocked.length ? h('div', { class: 'muted', text: `blocks ${row.blocked.join(', ')}` }) : null),
      h('td', { class: 'error' },
        error ? [h('span', { class: `badge kind-${error.kind}`, text: error.kind }), ' ',
          h('span', { class: 'error-message', text: error.message })] : '—'),
      h('td', { class: 'num', text: `${count(row.attempt)} / ${count(row.max_attempts)}` }),
      h('td', { text: time(error?.at_ms) }),
      h('td', { class: 'action' }, button,
        h('span', { class: 'retry-result', role: 'status', text: row.retry?.text ?? '' })),
    ];
  }

  /** POSTs the retry, shows its answer in the row, then asks for a refresh. */
  async retry(row) {
    const group = { ...row };
    delete group.retry;
    this.retries.set(row.job_id, { pending: true, text: 'retrying…', group });
    this.render();
    let text;
    try {
      const answer = await postJson(`/v1/jobs/${encodeURIComponent(row.job_id)}/retry`);
      text = `requeued: ${answer.requeued?.length ? answer.requeued.join(', ') : 'nothing'}`;
    } catch (e) {
      text = e.message;
    }
    this.retries.set(row.job_id, { pending: false, text, group });
    this.render();
    this.onRetried();
  }
}

/**
 * One entry per job, in the order listed: `stages` that are dead (the dead-lettered ones), the
 * stages they hold up (`blocked`: the API lists a dead job's blocked runs too), and the dead
 * stage's error and attempts.
 */
function groupByJob(items) {
  const jobs = new Map();
  for (const item of items) {
    if (!jobs.has(item.job_id)) jobs.set(item.job_id, []);
    jobs.get(item.job_id).push(item);
  }
  return [...jobs.values()].map((stages) => {
    const dead = stages.filter((s) => s.state === 'dead');
    const withError = stages.filter((s) => s.last_error);
    const shown = dead.length ? dead : withError.length ? withError : stages;
    const main = shown[0];
    return {
      job_id: main.job_id,
      asset_id: main.asset_id,
      file_name: main.file_name,
      stages: shown.map((s) => s.stage),
      blocked: stages.filter((s) => !shown.includes(s)).map((s) => s.stage),
      attempt: main.attempt,
      max_attempts: main.max_attempts,
      last_error: main.last_error,
    };
  });
}
