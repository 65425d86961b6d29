/**
 * The asset page's joint table (`#joints`): one row per joint of record.json, limits shown in
 * degrees (revolute) or millimetres (prismatic), with a checkbox per movable joint choosing
 * whether the viewer animates it.
 */

import { h, table } from './dom.js';
import { degrees, millimetres, num, vec3 } from './format.js';

const MOVABLE = new Set(['revolute', 'continuous', 'prismatic']);

/**
 * @param {object} record the asset's record.json.
 * @param {(jointName: string, on: boolean) => void} onToggle a joint's animate checkbox changed.
 * @returns {{element: HTMLTableElement, setEnabled: (on: boolean) => void}}
 */
export function jointsTable(record, onToggle) {
  const partName = new Map(record.parts.map((p) => [p.id, p.name]));
  const nameOf = (id) => `${partName.get(id) ?? 'part'} (${id})`;
  const element = table({ id: 'joints', class: 'data' }, `Joints (${record.joints.length}); the root part is ${nameOf(record.root)}`,
    ['Animate', 'Joint', 'Kind', 'Parent → child', 'Axis (object frame)', 'Pivot (m)', 'Limits', 'Damping', 'Friction', 'Coupled parts']);
  const boxes = [];
  for (const joint of record.joints) {
    const movable = MOVABLE.has(joint.kind);
    const box = movable
      ? h('input', { type: 'checkbox', checked: true, disabled: true, 'aria-label': `Animate ${joint.name}`,
        onchange: (e) => onToggle(joint.name, e.target.checked) })
      : null;
    if (box) boxes.push(box);
    element.tBodies[0].append(h('tr', { 'data-joint': joint.name, 'data-kind': joint.kind },
      h('td', {}, box ?? '—'),
      h('th', { scope: 'row', text: joint.name }),
      h('td', {}, h('span', { class: `badge joint-${joint.kind}`, text: joint.kind })),
      h('td', { text: `${nameOf(joint.parent)} → ${nameOf(joint.child)}` }),
      h('td', { class: 'num', text: vec3(joint.axis_in_object) }),
      h('td', { class: 'num', text: vec3(joint.pivot_in_object_m) }),
      h('td', { class: 'num', text: limitsOf(joint) }),
      h('td', { class: 'num', text: movable ? `${num(joint.damping)} ${dampingUnit(joint.kind)}` : '—' }),
      h('td', { class: 'num', text: movable ? num(joint.friction) : '—' }),
      h('td', { text: (joint.coupled_parts ?? []).map(nameOf).join(', ') || '—' })));
  }
  return {
    element,
    setEnabled: (on) => boxes.forEach((box) => { box.disabled = !on; }),
  };
}

function limitsOf(joint) {
  const l = joint.limits;
  if (joint.kind === 'continuous') return 'unlimited';
  if (!l) return '—';
  if (joint.kind === 'revolute') return `${degrees(l.lower)} … ${degrees(l.upper)}`;
  if (joint.kind === 'prismatic') return `${millimetres(l.lower)} … ${millimetres(l.upper)}`;
  return '—';
}

function dampingUnit(kind) {
  return kind === 'prismatic' ? 'N·s/m' : 'N·m·s/rad';
}
