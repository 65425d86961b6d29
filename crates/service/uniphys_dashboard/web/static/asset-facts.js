/**
 * The asset page's facts: the header (asset, latest job, state) and the convert stage's summary
 * (verdict and dataset figures).
 */

import { h, replaceChildren } from './dom.js';
import { bytes, count, duration, mass, time, vec3 } from './format.js';

/** The page heading and the asset's and job's facts, from `GET /v1/assets/{id}`. */
export function renderHeader(header, id, detail) {
  const { asset, job } = detail;
  const fileName = asset.source_key?.split('/').pop() ?? '';
  replaceChildren(header,
    h('h1', {}, `Asset ${id} `, h('span', { class: 'file-name', text: fileName }), ' ',
      h('span', { class: `badge state-${job?.state ?? 'none'}`, 'data-job-state': job?.state ?? '', text: job?.state ?? 'no job' })),
    h('dl', { class: 'facts' },
      fact('Job', job?.id ?? '—'),
      fact('Priority', job ? String(job.priority) : '—'),
      fact('Submitted', time(asset.created_at_ms)),
      fact('Finished', time(job?.finished_at_ms)),
      fact('Size', bytes(asset.size_bytes)),
      fact('Content', h('code', { title: asset.content_digest, text: `${(asset.content_digest ?? '').slice(0, 19)}…` }))));
}

/** The convert stage's summary: the verdict and the dataset figures (empty before it). */
export function renderSummary(element, job) {
  const convert = (job?.stages ?? []).find((s) => s.summary && 'passed' in s.summary);
  if (!convert) {
    replaceChildren(element);
    return;
  }
  const s = convert.summary;
  const dataset = s.dataset ?? {};
  const secs = Object.entries(s.stage_secs ?? {}).map(([name, v]) => `${name} ${duration(v * 1000)}`).join(', ');
  replaceChildren(element, h('section', { class: 'card' },
    h('h2', {}, `${s.name ?? 'Model'} `, h('span', { class: `badge verdict-${s.passed ? 'passed' : 'failed'}`, text: s.passed ? 'passed' : 'failed' })),
    h('dl', { class: 'facts' },
      fact('Category', dataset.category ?? '—'),
      fact('Mass', mass(dataset.mass_kg)),
      fact('Size (m)', vec3(dataset.size_m)),
      fact('Parts', count(s.parts)),
      fact('Joints', count(s.joints)),
      fact('Materials', Object.entries(dataset.materials ?? {}).map(([m, n]) => `${m} × ${n}`).join(', ') || '—'),
      fact('Joint types', Object.entries(dataset.joint_types ?? {}).map(([k, n]) => `${k} × ${n}`).join(', ') || '—'),
      fact('Files', count(s.files)),
      secs ? fact('Pipeline time', secs) : null)));
}

function fact(term, value) {
  return h('div', {}, h('dt', { text: term }), h('dd', {}, value));
}
