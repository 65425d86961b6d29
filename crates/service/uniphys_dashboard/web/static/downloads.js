/**
 * The asset page's download list (`#downloads`): one link per artifact with its size, grouped
 * by stage; a stage's sub-folders (`meshes/`, `parts/`, …) are folded. A link's click fetches
 * the file with the API key (a plain link would answer 401) and saves it.
 */

import { h, replaceChildren } from './dom.js';
import { bytes, count } from './format.js';
import { downloadWithKey } from './download.js';

/** Fills the `#downloads` list with `items` of `GET /v1/assets/{id}/artifacts`. */
export function renderDownloads(list, items) {
  if (items.length === 0) {
    replaceChildren(list, h('li', { class: 'muted', text: 'No artifacts yet.' }));
    return;
  }
  replaceChildren(list, [...groupBy(items, (a) => a.stage)].map(([stage, files]) => {
    const folders = groupBy(files, (a) => (a.name.includes('/') ? a.name.slice(0, a.name.lastIndexOf('/') + 1) : ''));
    const top = folders.get('') ?? [];
    folders.delete('');
    return h('li', { class: 'stage-files' }, h('strong', { text: stage }),
      h('ul', {},
        top.map(fileItem),
        [...folders].map(([folder, inside]) => h('li', {}, h('details', {},
          h('summary', { text: `${folder} (${count(inside.length)} files, ${bytes(inside.reduce((n, a) => n + a.bytes, 0))})` }),
          h('ul', {}, inside.map(fileItem)))))));
  }));
}

/** One artifact: its link (named by its path under the stage) and size. */
function fileItem(item) {
  const fileName = item.name.split('/').pop();
  const status = h('span', { class: 'download-status', role: 'status' });
  const link = h('a', {
    href: item.href, download: fileName, 'data-path': item.path, text: item.name,
    onclick: async (event) => {
      event.preventDefault();
      status.textContent = ' downloading…';
      try {
        await downloadWithKey(item.href, fileName);
        status.textContent = '';
      } catch (e) {
        status.textContent = ` ${e.message}`;
      }
    },
  });
  return h('li', { 'data-artifact': item.path }, link, ' ', h('span', { class: 'size', text: bytes(item.bytes) }), status);
}

/** Items by `keyOf(item)`, in first-seen order. */
function groupBy(items, keyOf) {
  const groups = new Map();
  for (const item of items) {
    const key = keyOf(item);
    if (!groups.has(key)) groups.set(key, []);
    groups.get(key).push(item);
  }
  return groups;
}
