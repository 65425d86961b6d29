/**
 * The overview page (`#/`): per-stage queue state, depth and throughput charts over the history,
 * the tenant's job counts, running work and dead letters. Refreshed every 2 s.
 */

import { getJson, query } from './api.js';
import { lineChart, legend } from './charts.js';
import { DeadLetters } from './dead-letters.js';
import { h, replaceChildren, syncRows, table } from './dom.js';
import { count, duration, num } from './format.js';
import { Freshness } from './freshness.js';
import { History } from './history.js';
import { css } from './palette.js';
import { Poller } from './poller.js';
import { runningTable, updateRunningTable } from './running-work.js';

const POLL_MS = 2000;
const WORK_LIMIT = 50;
const JOB_STATES = ['running', 'succeeded', 'dead', 'cancelled'];

export function mount(root) {
  const history = new History(720);
  const colors = new Map();
  const colorOf = (stage) => {
    if (!colors.has(stage)) colors.set(stage, css(colors.size));
    return colors.get(stage);
  };

  const stageTable = table({ id: 'stage-table', class: 'data' }, 'Stages', []);
  const tenant = h('section', { id: 'tenant-summary', class: 'card', 'aria-label': 'Jobs of this tenant' });
  const depthChart = h('figure', { id: 'chart-depth', class: 'chart-box' });
  const throughputChart = h('figure', { id: 'chart-throughput', class: 'chart-box' });
  const running = runningTable();
  const runningMore = h('p', { class: 'more' });
  const dead = new DeadLetters(() => poller.refresh());
  const deadMore = h('p', { class: 'more' });

  const section = h('section', { id: 'overview', class: 'page' }, h('h1', { text: 'Overview' }));
  root.append(section);

  const poller = new Poller(async (signal) => {
    const [overview, runningWork, deadWork] = await Promise.all([
      getJson(`/v1/overview${query({ since_ms: history.lastAtMs })}`, { signal }),
      getJson(`/v1/work${query({ state: 'running', limit: WORK_LIMIT })}`, { signal }),
      getJson(`/v1/work${query({ state: 'dead', limit: WORK_LIMIT })}`, { signal }),
    ]);
    history.append(overview.history?.samples);
    const stages = overview.stages ?? [];
    stages.forEach((s) => colorOf(s.stage));
    renderStages(stageTable, stages, overview.window_secs);
    renderTenant(tenant, overview.tenant);
    renderCharts(depthChart, throughputChart, history, stages, colorOf, overview.generated_at_ms);
    updateRunningTable(running, runningWork.items);
    more(runningMore, runningWork.next, 'running', runningWork.items.length);
    dead.update(deadWork.items);
    more(deadMore, deadWork.next, 'dead', deadWork.items.length);
  }, { intervalMs: POLL_MS, onChange: () => freshness.update() });
  const freshness = new Freshness(poller, section);

  section.append(
    freshness.element,
    tenant,
    h('div', { class: 'scroll' }, stageTable),
    h('div', { class: 'charts' }, depthChart, throughputChart),
    h('div', { class: 'scroll' }, running), runningMore,
    h('div', { class: 'scroll' }, dead.element), deadMore,
  );
  poller.start();
  return () => {
    poller.stop();
    freshness.dispose();
  };
}

const STAGE_COLUMNS = (windowSecs) => [
  'Stage', 'Claims', 'Depth', 'Ready', 'Backing off', 'Blocked', 'Running', 'Failed',
  `Succeeded (${windowSecs} s)`, `Failed (${windowSecs} s)`, 'Throughput', 'Oldest waiting',
];

function renderStages(element, stages, windowSecs = 60) {
  const headings = STAGE_COLUMNS(windowSecs);
  const headRow = element.tHead.rows[0];
  if (headRow.cells.length !== headings.length || headRow.cells[8].textContent !== headings[8]) {
    replaceChildren(headRow, headings.map((text) => h('th', { scope: 'col', text })));
  }
  syncRows(element.tBodies[0], stages, {
    keyOf: (s) => s.stage,
    empty: 'No stages.',
    rowProps: (s) => ({ dataset: { stage: s.stage } }),
    cells: (s) => [
      h('th', { scope: 'row', text: s.stage }),
      h('td', {}, claims(s)),
      ...['depth', 'ready', 'backing_off', 'blocked', 'running', 'failed', 'succeeded_in_window', 'failed_in_window']
        .map((field) => h('td', { class: 'num', text: count(s[field]) })),
      h('td', { class: 'num', text: `${num(s.throughput_per_sec)} /s` }),
      h('td', { class: 'num', text: s.oldest_waiting_age_ms ? duration(s.oldest_waiting_age_ms) : '—' }),
    ],
  });
}

/** Whether a stage's claims are paused, served, or not taken by any worker. */
function claims(s) {
  if (s.paused) return h('span', { class: 'badge state-paused', text: 'paused' });
  if (s.unserved) {
    return h('span', {
      class: 'badge state-unserved',
      text: 'no worker',
      title: 'Work has waited the whole window and no worker took any: start a worker whose UNIPHYS_STAGES includes this stage.',
    });
  }
  return h('span', { class: 'badge state-active', text: 'active' });
}

function renderTenant(element, tenant) {
  if (!tenant) return;
  const jobs = tenant.jobs ?? {};
  replaceChildren(element,
    h('h2', { text: tenant.name ? `Jobs of ${tenant.name} (${tenant.id})` : `Jobs of ${tenant.id}` }),
    h('dl', { class: 'counts' }, JOB_STATES.map((state) => h('div', { class: `count state-${state}` },
      h('dt', {}, h('a', { href: `#/assets?state=${state}`, text: state })),
      h('dd', { 'data-state': state, text: count(jobs[state] ?? 0) })))));
}

function renderCharts(depthBox, throughputBox, history, stages, colorOf, nowMs) {
  const names = [...new Set([...stages.map((s) => s.stage), ...history.stageNames()])];
  const seriesOf = (field) => names.map((name) => ({ name, color: colorOf(name), points: history.points(name, field) }));
  const span = history.samples.length ? duration(nowMs - history.samples[0].at_ms) : 'no samples yet';
  const depth = seriesOf('depth');
  replaceChildren(depthBox,
    h('figcaption', { text: `Queue depth per stage (last ${span})` }),
    lineChart(depth, { nowMs, label: 'Queue depth per stage over time', format: count }),
    legend(depth));
  const throughput = seriesOf('throughput_per_sec');
  replaceChildren(throughputBox,
    h('figcaption', { text: `Throughput per stage, runs/s (last ${span})` }),
    lineChart(throughput, { nowMs, label: 'Throughput per stage over time', format: (v) => num(v, 2) }),
    legend(throughput));
}

/** A link to the full list when the first page of work was not all of it. */
function more(element, next, state, shown) {
  replaceChildren(element, next
    ? [`Only the newest ${shown} items are shown. `, h('a', { href: `#/assets?state=${state}`, text: `All ${state} assets…` })]
    : []);
}
