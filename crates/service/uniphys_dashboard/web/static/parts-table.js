/**
 * The asset page's part list (`#parts`): each part of record.json with the colour the viewer
 * draws it in, its material and mass.
 */

import { h, table } from './dom.js';
import { count, mass, vec3 } from './format.js';
import { css } from './palette.js';

/** A `#parts` table of `record.parts`; the n-th part gets the n-th palette colour. */
export function partsTable(record) {
  const element = table({ id: 'parts', class: 'data' }, `Parts (${record.parts.length}), coloured as in the 3D view`,
    ['Colour', 'Part', 'Material', 'Mass', 'Size (m)', 'Triangles']);
  record.parts.forEach((part, i) => {
    const material = part.properties?.material?.value;
    const [lo, hi] = part.bounds_in_object_m ?? [];
    const size = lo && hi ? vec3(hi.map((x, k) => x - lo[k])) : '—';
    element.tBodies[0].append(h('tr', { 'data-part': part.id },
      h('td', {}, h('span', { class: 'swatch', style: `background:${css(i)}`, 'aria-hidden': 'true' })),
      h('th', { scope: 'row', text: `${part.name} (${part.id})${part.id === record.root ? ', root' : ''}` }),
      h('td', { text: material ? `${material.category}${material.subtype ? ` (${material.subtype})` : ''}` : '—' }),
      h('td', { class: 'num', text: mass(part.mass?.mass_kg?.value) }),
      h('td', { class: 'num', text: size }),
      h('td', { class: 'num', text: count(part.triangle_count) })));
  });
  return element;
}
