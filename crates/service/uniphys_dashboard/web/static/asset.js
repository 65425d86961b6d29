/**
 * The asset page (`#/assets/<asset id>`): the latest job's stages (refreshed every 2 s while the
 * job runs), and once the convert stage wrote its files: its rendered preview, the 3D viewer,
 * joints, parts, verification report and downloads.
 *
 * The viewer (and with it three.js) is imported dynamically: when it cannot load, `#viewer`
 * shows why (and gets `data-error`) while the rest of the page works.
 */

import { getBlob, getJson, getText } from './api.js';
import { h, replaceChildren } from './dom.js';
import { renderHeader, renderSummary } from './asset-facts.js';
import { Freshness } from './freshness.js';
import { jointsTable } from './joints-table.js';
import { partsTable } from './parts-table.js';
import { Poller } from './poller.js';
import { renderReport } from './report.js';
import { renderDownloads } from './downloads.js';
import { stageRunsTable, updateStageRuns } from './stage-runs.js';

const POLL_MS = 2000;

export function mount(root, { id }) {
  const base = `/v1/assets/${encodeURIComponent(id)}`;
  const controller = new AbortController();
  const signal = controller.signal;
  let viewer = null;
  let artifactsKey = null;
  let modelStarted = false;
  let previewUrl = null;

  const header = h('header', { class: 'asset-header' }, h('h1', { text: `Asset ${id}` }));
  const stages = stageRunsTable();
  const summary = h('div', { class: 'model-summary' });
  const viewerBox = h('div', { id: 'viewer', class: 'viewer' },
    h('p', { class: 'viewer-message', text: 'The 3D view appears when the convert stage has written its parts.' }));
  const animate = checkbox('animate', 'Animate joints', (on) => viewer?.setAnimating(on));
  const axes = checkbox('show-axes', 'Show joint axes', (on) => viewer?.setAxesVisible(on));
  const model = h('div', { class: 'model' });
  const preview = h('figure', { id: 'preview', class: 'preview', hidden: true });
  const report = h('section', { id: 'report', class: 'card' }, h('h2', { text: 'Verification' }),
    h('p', { class: 'muted', text: 'No report yet.' }));
  const downloads = h('ul', { id: 'downloads', class: 'downloads' });

  const section = h('section', { id: 'asset', class: 'page' },
    h('p', { class: 'crumbs' }, h('a', { href: '#/assets', text: 'Assets' }), ' / ', id),
    header);
  root.append(section);

  const poller = new Poller(async () => {
    let detail;
    try {
      detail = await getJson(base, { signal });
    } catch (e) {
      if (e.status !== 404) throw e;
      replaceChildren(header, h('h1', { text: `Asset ${id}` }), h('p', { class: 'banner error', role: 'alert', text: e.message }));
      freshness.pausedText = 'not refreshing';
      poller.pause();
      return;
    }
    renderHeader(header, id, detail);
    updateStageRuns(stages, detail.job);
    renderSummary(summary, detail.job);
    const key = (detail.job?.stages ?? []).filter((s) => s.state === 'succeeded').map((s) => s.name).join(',');
    if (key !== artifactsKey) {
      const list = await getJson(`${base}/artifacts`, { signal });
      artifactsKey = key;
      renderDownloads(downloads, list.items);
      showPreview(list.items);
      if (!modelStarted && list.items.some((a) => a.name === 'record.json')) {
        modelStarted = true;
        loadModel(list.items).catch((e) => {
          showError(model, 'Cannot show the model', e);
          if (e.name !== 'AbortError') failViewer(e.message);
        });
      }
    }
    if (detail.job?.state !== 'running') poller.pause();
  }, { intervalMs: POLL_MS, onChange: () => freshness.update() });
  const freshness = new Freshness(poller, section, 'not refreshing: the job has finished');

  section.append(
    freshness.element,
    h('div', { class: 'scroll' }, stages),
    summary,
    h('h2', { text: 'Model' }),
    preview,
    h('div', { class: 'viewer-block' }, viewerBox,
      h('div', { class: 'viewer-controls' }, animate.label, axes.label,
        h('span', { class: 'muted', text: 'Drag to orbit, scroll to zoom, right-drag to pan.' }))),
    model,
    report,
    h('section', { class: 'card' }, h('h2', { text: 'Downloads' }), downloads));
  poller.start();

  /** Fetches record.json and report.json, then fills the model sections and starts the viewer. */
  async function loadModel(items) {
    const record = items.find((a) => a.name === 'record.json');
    const files = new Map(items.filter((a) => a.stage === record.stage).map((a) => [a.name, a]));
    const reportItem = files.get('report.json');
    if (reportItem) {
      getText(reportItem.href, { signal })
        .then((text) => renderReport(report, JSON.parse(text)))
        .catch((e) => showError(report, 'Cannot read report.json', e));
    }
    let data;
    try {
      data = JSON.parse(await getText(record.href, { signal }));
    } catch (e) {
      showError(model, 'Cannot read record.json', e);
      failViewer(`record.json unavailable: ${e.message}`);
      return;
    }
    const joints = jointsTable(data, (name, on) => viewer?.setJointEnabled(name, on));
    replaceChildren(model,
      h('section', { class: 'card' }, h('div', { class: 'scroll' }, joints.element)),
      h('section', { class: 'card' }, h('div', { class: 'scroll' }, partsTable(data))));
    await startViewer(data, files, joints);
  }

  async function startViewer(record, files, joints) {
    replaceChildren(viewerBox, h('p', { class: 'viewer-message', text: 'Loading the parts…' }));
    let createViewer;
    try {
      // three.js alone first: a stub that throws then says why, instead of a missing export.
      await import('three');
      ({ createViewer } = await import('./viewer.js'));
    } catch (e) {
      failViewer(`The 3D viewer could not load (${e.message}).`);
      return;
    }
    try {
      const created = await createViewer(viewerBox, {
        record,
        loadObj: (partId) => {
          const item = files.get(`parts/part_${partId}.obj`);
          if (!item) throw new Error(`no artifact parts/part_${partId}.obj`);
          return getText(item.href, { signal });
        },
      });
      if (signal.aborted) {
        created.dispose();
        return;
      }
      viewer = created;
      viewerBox.querySelector('.viewer-message')?.remove();
      viewer.setAnimating(animate.input.checked);
      viewer.setAxesVisible(axes.input.checked);
      animate.input.disabled = false;
      axes.input.disabled = false;
      joints.setEnabled(true);
      viewerBox.dataset.parts = String(viewer.partCount);
      viewerBox.dataset.joints = String(record.joints.length);
      viewerBox.dataset.ready = 'true';
    } catch (e) {
      if (e.name !== 'AbortError') failViewer(e.message);
    }
  }

  /** Shows `renders/preview.png` (four views, parts in the viewer's colours) when there is one. */
  function showPreview(items) {
    const item = items.find((a) => a.name === 'renders/preview.png');
    if (!item || previewUrl) return;
    getBlob(item.href, { signal })
      .then((blob) => {
        previewUrl = URL.createObjectURL(blob);
        replaceChildren(preview,
          h('img', { src: previewUrl, alt: 'The asset at rest from four sides, each part in its colour' }),
          h('figcaption', { class: 'muted', text: 'Rendered by the convert stage (renders/preview.png).' }));
        preview.hidden = false;
      })
      .catch((e) => showError(preview, 'Cannot show the preview', e));
  }

  function failViewer(message) {
    viewerBox.dataset.error = message;
    replaceChildren(viewerBox, h('p', { class: 'viewer-message error', role: 'alert', text: message }));
  }

  return () => {
    controller.abort();
    poller.stop();
    freshness.dispose();
    viewer?.dispose();
    viewer = null;
    if (previewUrl) URL.revokeObjectURL(previewUrl);
  };
}

/** An initially disabled checkbox with its label; `onChange(checked)`. */
function checkbox(id, text, onChange) {
  const input = h('input', { type: 'checkbox', id, checked: true, disabled: true,
    onchange: (e) => onChange(e.target.checked) });
  return { input, label: h('label', { for: id }, input, ` ${text}`) };
}

function showError(element, what, error) {
  if (error.name === 'AbortError') return;
  replaceChildren(element, h('p', { class: 'banner error', role: 'alert', text: `${what}: ${error.message}` }));
}
