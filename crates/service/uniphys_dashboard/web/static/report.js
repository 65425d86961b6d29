/**
 * The asset page's verification summary (`#report`) from report.json: passed or failed, the
 * failures, and every check (subject, name, outcome, message) by section. Sections with a
 * warning or failure start open.
 */

import { h, replaceChildren, table } from './dom.js';

/** Fills `element` with the summary of `report` (report.json). */
export function renderReport(element, report) {
  const checks = (report.sections ?? []).flatMap((s) => s.checks ?? []);
  const tally = {};
  for (const c of checks) tally[c.outcome] = (tally[c.outcome] ?? 0) + 1;
  const verdict = report.passed ? 'passed' : 'failed';
  replaceChildren(element,
    h('h2', {}, 'Verification ', h('span', { class: `badge verdict-${verdict}`, 'data-passed': String(Boolean(report.passed)), text: verdict })),
    h('p', { class: 'tally', text: Object.entries(tally).map(([outcome, n]) => `${n} ${outcome}`).join(', ') || 'no checks' }),
    report.failures?.length
      ? h('ul', { class: 'failures' }, report.failures.map((f) => h('li', { class: 'error-message', text: f })))
      : null,
    (report.sections ?? []).map((section) => {
      const bad = (section.checks ?? []).filter((c) => c.outcome !== 'pass').length;
      const list = table({ class: 'data checks' }, null, ['Subject', 'Check', 'Outcome', 'Message']);
      for (const c of section.checks ?? []) {
        list.tBodies[0].append(h('tr', { 'data-check': c.check, 'data-outcome': c.outcome },
          h('td', { text: c.subject }),
          h('th', { scope: 'row', text: c.check }),
          h('td', {}, h('span', { class: `badge outcome-${c.outcome}`, text: c.outcome })),
          h('td', { text: c.message })));
      }
      return h('details', { class: 'section', open: bad > 0, 'data-section': section.name },
        h('summary', { text: `${section.name}: ${section.checks?.length ?? 0} checks${bad ? `, ${bad} not passed` : ''}` }),
        h('div', { class: 'scroll' }, list));
    }),
    report.notes?.length
      ? h('details', { class: 'section' }, h('summary', { text: `Notes (${report.notes.length})` }),
        h('ul', {}, report.notes.map((n) => h('li', { text: n }))))
      : null);
}
