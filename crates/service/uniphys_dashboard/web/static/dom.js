/**
 * Building DOM nodes without innerHTML: every text from the API lands as a text node, never as
 * markup.
 */

const SVG_NS = 'http://www.w3.org/2000/svg';

/** The JSON of the item each row of {@link syncRows} shows. */
const rowSignatures = new WeakMap();

/**
 * Creates an HTML element. `props`: `class`, `text`, `dataset` (an object), `on<event>`
 * functions (listeners), `hidden`/`disabled`/`checked`/`value` (set as properties), anything
 * else as an attribute (skipped when null, undefined or false). Children: nodes, strings,
 * numbers, arrays of them; null and false are skipped.
 */
export function h(tag, props = {}, ...children) {
  return build(document.createElement(tag), props, children);
}

/** Creates an SVG element, with the same `props` and children as {@link h}. */
export function svg(tag, props = {}, ...children) {
  return build(document.createElementNS(SVG_NS, tag), props, children);
}

const PROPERTIES = new Set(['hidden', 'disabled', 'checked', 'value', 'open']);

function build(el, props, children) {
  for (const [name, value] of Object.entries(props ?? {})) {
    if (name === 'class') el.setAttribute('class', value);
    else if (name === 'text') el.textContent = value;
    else if (name === 'dataset') Object.assign(el.dataset, value);
    else if (name.startsWith('on') && typeof value === 'function') {
      el.addEventListener(name.slice(2), value);
    } else if (PROPERTIES.has(name)) el[name] = value;
    else if (value !== null && value !== undefined && value !== false) {
      el.setAttribute(name, value === true ? '' : String(value));
    }
  }
  append(el, children);
  return el;
}

function append(el, children) {
  for (const child of children) {
    if (child === null || child === undefined || child === false) continue;
    if (Array.isArray(child)) append(el, child);
    else el.append(child instanceof Node ? child : String(child));
  }
}

/** Replaces every child of `el` with `children`. */
export function replaceChildren(el, ...children) {
  el.replaceChildren();
  append(el, children);
  return el;
}

/**
 * Brings a table body in line with `items`, one `<tr>` per item keyed by `keyOf(item)`. Rows
 * are reused, and a row's cells are rebuilt only when its item changed (compared as JSON), so
 * focus, open `<details>` and button states survive a refresh that changed nothing.
 * `rowProps(item)` gives the row's attributes; `cells(item)` its `<td>`/`<th>` elements; with no
 * items, the body shows the one-row message `empty`.
 */
export function syncRows(tbody, items, { keyOf, rowProps = () => ({}), cells, empty = 'None.' }) {
  const old = new Map();
  for (const tr of [...tbody.rows]) {
    if (tr.classList.contains('empty')) tr.remove();
    else old.set(tr.dataset.key, tr);
  }
  const rows = items.map((item) => {
    const key = String(keyOf(item));
    const signature = JSON.stringify(item);
    let tr = old.get(key);
    if (tr && rowSignatures.get(tr) === signature) return tr;
    const props = rowProps(item);
    tr = h('tr', { ...props, dataset: { ...(props.dataset ?? {}), key } });
    rowSignatures.set(tr, signature);
    append(tr, [cells(item)]);
    return tr;
  });
  rows.forEach((tr, i) => {
    if (tbody.rows[i] !== tr) tbody.insertBefore(tr, tbody.rows[i] ?? null);
  });
  while (tbody.rows.length > rows.length) tbody.rows[rows.length].remove();
  if (rows.length === 0) {
    const columns = tbody.parentElement?.tHead?.rows[0]?.cells.length || 1;
    tbody.append(h('tr', { class: 'empty' }, h('td', { colspan: columns, class: 'muted', text: empty })));
  }
}

/** A `<table>` with a caption, a header row of `headings` and an empty `<tbody>`. */
export function table(props, caption, headings) {
  return h(
    'table',
    props,
    caption && h('caption', { text: caption }),
    h('thead', {}, h('tr', {}, headings.map((text) => h('th', { scope: 'col', text })))),
    h('tbody'),
  );
}
