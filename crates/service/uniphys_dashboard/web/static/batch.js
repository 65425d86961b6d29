/**
 * A batch's dataset statistics (`#/batches/<label>`): job counts, how many converted and passed,
 * bar charts of categories, materials and joint types, histograms of mass, size and parts per
 * asset, and the statistics as a JSON download.
 */

import { getJson } from './api.js';
import { barChart, histogram } from './charts.js';
import { h, replaceChildren } from './dom.js';
import { count, mass, num } from './format.js';
import { saveBlob } from './download.js';

const JOB_STATES = ['total', 'running', 'succeeded', 'dead', 'cancelled'];

export function mount(root, { label }) {
  const controller = new AbortController();
  const body = h('div', {}, h('p', { class: 'muted', text: 'loading…' }));
  root.append(h('section', { id: 'batch-stats', class: 'page' },
    h('p', { class: 'crumbs' }, h('a', { href: '#/batches', text: 'Batches' }), ' / ', label),
    h('h1', { text: `Batch ${label}` }),
    body));

  getJson(`/v1/batches/${encodeURIComponent(label)}/stats`, { signal: controller.signal })
    .then((stats) => replaceChildren(body, ...render(stats, label)))
    .catch((e) => {
      if (e.name !== 'AbortError') replaceChildren(body, h('p', { class: 'banner error', role: 'alert', text: e.message }));
    });
  return () => controller.abort();
}

function render(stats, label) {
  const jobs = stats.jobs ?? {};
  const download = h('button', {
    type: 'button', id: 'download-batch-json', text: 'Download statistics (JSON)',
    onclick: () => saveBlob(new Blob([JSON.stringify(stats, null, 2)], { type: 'application/json' }),
      `batch-${label.replace(/[^\w.-]+/g, '_')}-stats.json`),
  });
  const metres = (m) => `${num(m, 2)} m`;
  return [
    h('dl', { class: 'counts' },
      JOB_STATES.map((state) => h('div', { class: `count state-${state}` },
        h('dt', { text: state === 'total' ? 'jobs' : state }),
        h('dd', { 'data-field': `jobs.${state}`, text: count(jobs[state] ?? 0) }))),
      h('div', { class: 'count' }, h('dt', { text: 'converted' }), h('dd', { 'data-field': 'converted', text: count(stats.converted) })),
      h('div', { class: 'count' }, h('dt', { text: 'passed checks' }), h('dd', { 'data-field': 'passed', text: count(stats.passed) }))),
    h('p', {}, download),
    h('div', { class: 'charts' },
      figure('chart-categories', 'Categories (assets)', barChart(entries(stats.categories), { label: 'Assets per category', format: count })),
      figure('chart-materials', 'Materials (parts)', barChart(entries(stats.materials), { label: 'Parts per material', format: count })),
      figure('chart-joint-types', 'Joint types (joints)', barChart(entries(stats.joint_types), { label: 'Joints per type', format: count })),
      figure('chart-mass', `Mass per asset ${summary(stats.mass_kg, mass)}`,
        histogram(stats.mass_kg ?? {}, { label: 'Histogram of asset mass', formatEdge: mass, log: true })),
      figure('chart-size', `Largest dimension per asset ${summary(stats.size_m, metres)}`,
        histogram(stats.size_m ?? {}, { label: 'Histogram of the largest dimension', formatEdge: metres, log: true })),
      figure('chart-parts', `Parts per asset ${summary(stats.parts_per_asset, count)}`,
        histogram(stats.parts_per_asset ?? {}, { label: 'Histogram of parts per asset', formatEdge: (x) => num(x, 3) }))),
  ];
}

function figure(id, caption, chart) {
  return h('figure', { id, class: 'chart-box' }, h('figcaption', { text: caption }), chart);
}

function entries(counts) {
  return Object.entries(counts ?? {});
}

/** `(n = 12; min 1 kg, median 5 kg, max 30 kg)` of a histogram's summary. */
function summary(hist, format) {
  if (!hist || !hist.count) return '(no data)';
  return `(n = ${count(hist.count)}; min ${format(hist.min)}, median ${format(hist.median)}, max ${format(hist.max)})`;
}
