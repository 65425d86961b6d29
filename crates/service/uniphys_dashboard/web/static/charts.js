/**
 * Hand-drawn SVG charts: a time line chart (one path per series), a horizontal bar chart of
 * labelled counts and a histogram of binned values. Each returns an `<svg>` that scales to its
 * container's width (fixed viewBox); colours of bars and axes come from style.css.
 */

import { h, svg } from './dom.js';

const WIDTH = 640;
/** Bar charts and histograms sit three abreast: a narrower viewBox keeps their text legible. */
const NARROW_WIDTH = 440;
const LINE_HEIGHT = 220;
const MARGIN = { top: 14, right: 18, bottom: 34, left: 58 };

/**
 * Series over the last minutes, x = time relative to `nowMs`.
 * @param {{name: string, color: string, points: [number, number][]}[]} series points are
 *   `[unix ms, value]`, oldest first.
 * @param {{nowMs: number, label: string, format?: (y: number) => string}} options
 */
export function lineChart(series, { nowMs, label, format = String }) {
  const all = series.flatMap((s) => s.points);
  const x0 = Math.min(nowMs - 60_000, ...all.map(([t]) => t));
  const yTicks = niceTicks(Math.max(0, ...all.map(([, y]) => y)));
  const yMax = yTicks[yTicks.length - 1];
  const plot = frame(WIDTH, LINE_HEIGHT);
  const x = (t) => plot.left + ((t - x0) / (nowMs - x0)) * plot.width;
  const y = (v) => plot.bottom - (v / yMax) * plot.height;

  const root = chartRoot(WIDTH, LINE_HEIGHT, label);
  root.append(yAxis(plot, yTicks, y, format), timeAxis(plot, x0, nowMs, x));
  for (const s of series) {
    const d = s.points.map(([t, v], i) => `${i ? 'L' : 'M'}${x(t).toFixed(1)},${y(v).toFixed(1)}`);
    root.append(
      svg('path', { class: 'series', 'data-series': s.name, d: d.join(''), stroke: s.color },
        svg('title', { text: s.name })),
    );
    const last = s.points[s.points.length - 1];
    if (last) {
      root.append(svg('circle', { class: 'series-end', cx: x(last[0]), cy: y(last[1]), r: 3, fill: s.color },
        svg('title', { text: `${s.name}: ${format(last[1])}` })));
    }
  }
  return root;
}

/** A legend for {@link lineChart}: one swatch and name per series. */
export function legend(series) {
  return h('ul', { class: 'legend' },
    series.map((s) => h('li', {}, h('span', { class: 'swatch', style: `background:${s.color}` }), s.name)));
}

/**
 * Horizontal bars, one per `[label, value]` entry, largest first.
 * @param {[string, number][]} entries
 * @param {{label: string, format?: (v: number) => string}} options
 */
export function barChart(entries, { label, format = String }) {
  const rows = [...entries].sort((a, b) => b[1] - a[1] || a[0].localeCompare(b[0]));
  const rowHeight = 24;
  const labelWidth = Math.min(200, 16 + 6.6 * Math.max(4, ...rows.map(([l]) => short(l).length)));
  const height = 20 + Math.max(1, rows.length) * rowHeight;
  const root = chartRoot(NARROW_WIDTH, height, label);
  if (rows.length === 0) return noData(root, NARROW_WIDTH, height);
  const max = Math.max(...rows.map(([, v]) => v)) || 1;
  const barSpace = NARROW_WIDTH - labelWidth - 50;
  rows.forEach(([name, value], i) => {
    const top = 10 + i * rowHeight;
    const width = (value / max) * barSpace;
    root.append(
      svg('text', { class: 'bar-label', x: labelWidth - 8, y: top + rowHeight / 2, 'text-anchor': 'end',
        'dominant-baseline': 'middle', text: short(name) }),
      svg('rect', { class: 'bar', 'data-label': name, x: labelWidth, y: top + 3, width: Math.max(width, 0),
        height: rowHeight - 6, rx: 2 }, svg('title', { text: `${name}: ${format(value)}` })),
      svg('text', { class: 'bar-value', x: labelWidth + width + 6, y: top + rowHeight / 2,
        'dominant-baseline': 'middle', text: format(value) }),
    );
  });
  return root;
}

/**
 * Counts per bin, bins drawn side by side at equal widths (log-spaced edges read naturally),
 * with the median marked.
 * @param {{edges: number[], counts: number[], median?: number, count?: number}} histogram
 *   `edges.length === counts.length + 1`.
 * @param {{label: string, formatEdge?: (x: number) => string, log?: boolean}} options
 */
export function histogram({ edges = [], counts = [], median = null }, { label, formatEdge = String, log = false }) {
  const height = LINE_HEIGHT;
  const root = chartRoot(NARROW_WIDTH, height, label);
  const total = counts.reduce((a, b) => a + b, 0);
  if (counts.length === 0 || edges.length !== counts.length + 1 || total === 0) {
    return noData(root, NARROW_WIDTH, height);
  }
  const plot = frame(NARROW_WIDTH, height);
  const yTicks = niceTicks(Math.max(...counts), true);
  const yMax = yTicks[yTicks.length - 1];
  const binWidth = plot.width / counts.length;
  const y = (v) => plot.bottom - (v / yMax) * plot.height;
  root.append(yAxis(plot, yTicks, y, String));
  counts.forEach((n, i) => {
    const range = `${formatEdge(edges[i])} – ${formatEdge(edges[i + 1])}`;
    root.append(svg('rect', { class: 'bar', 'data-bin': i, x: plot.left + i * binWidth + 1, y: y(n),
      width: Math.max(binWidth - 2, 1), height: plot.bottom - y(n) },
    svg('title', { text: `${range}: ${n}` })));
  });
  const every = Math.ceil(edges.length / 6);
  const axis = svg('g', { class: 'axis' },
    svg('line', { x1: plot.left, x2: plot.right, y1: plot.bottom, y2: plot.bottom }));
  edges.forEach((edge, i) => {
    if (i % every !== 0 && i !== edges.length - 1) return;
    // The outermost labels stay inside the chart.
    const anchor = i === 0 ? 'start' : i === edges.length - 1 ? 'end' : 'middle';
    axis.append(svg('text', { x: plot.left + i * binWidth, y: plot.bottom + 16, 'text-anchor': anchor,
      text: formatEdge(edge) }));
  });
  root.append(axis);
  if (median !== null && median !== undefined) {
    const mx = plot.left + binPosition(edges, median, log) * binWidth;
    root.append(svg('g', { class: 'median' },
      svg('line', { x1: mx, x2: mx, y1: plot.top, y2: plot.bottom }),
      svg('text', { x: mx + 4, y: plot.top + 10, text: `median ${formatEdge(median)}` })));
  }
  return root;
}

/** Where `value` falls in bin units (0 at the first edge), interpolating in log space if `log`. */
function binPosition(edges, value, log) {
  const t = log ? Math.log : (v) => v;
  for (let i = 0; i < edges.length - 1; i += 1) {
    if (value <= edges[i + 1] || i === edges.length - 2) {
      const span = t(edges[i + 1]) - t(edges[i]);
      const within = span > 0 ? (t(Math.max(value, edges[i])) - t(edges[i])) / span : 0;
      return i + Math.min(1, Math.max(0, within));
    }
  }
  return 0;
}

/** Ticks from 0 up to at least `max`, about four steps of 1, 2 or 5 × 10ⁿ. */
function niceTicks(max, integers = false) {
  const top = max > 0 ? max : 1;
  const raw = top / 4;
  const power = 10 ** Math.floor(Math.log10(raw));
  let step = [1, 2, 5, 10].map((m) => m * power).find((s) => s >= raw);
  if (integers) step = Math.max(1, Math.round(step));
  const ticks = [];
  for (let v = 0; v < top + step / 2; v += step) ticks.push(Number(v.toPrecision(12)));
  if (ticks[ticks.length - 1] < top) ticks.push(Number((ticks[ticks.length - 1] + step).toPrecision(12)));
  return ticks;
}

function frame(width, height) {
  return {
    left: MARGIN.left,
    right: width - MARGIN.right,
    top: MARGIN.top,
    bottom: height - MARGIN.bottom,
    width: width - MARGIN.left - MARGIN.right,
    height: height - MARGIN.top - MARGIN.bottom,
  };
}

function chartRoot(width, height, label) {
  return svg('svg', { class: 'chart', viewBox: `0 0 ${width} ${height}`, role: 'img', 'aria-label': label,
    preserveAspectRatio: 'xMidYMid meet' });
}

function noData(root, width, height) {
  root.append(svg('text', { class: 'no-data', x: width / 2, y: height / 2, 'text-anchor': 'middle', text: 'no data' }));
  return root;
}

function yAxis(plot, ticks, y, format) {
  return svg('g', { class: 'axis' },
    ticks.map((v) => [
      svg('line', { class: 'grid', x1: plot.left, x2: plot.right, y1: y(v), y2: y(v) }),
      svg('text', { x: plot.left - 6, y: y(v), 'text-anchor': 'end', 'dominant-baseline': 'middle', text: format(v) }),
    ]));
}

const TIME_STEPS_S = [5, 10, 15, 30, 60, 120, 300, 600, 900, 1800, 3600];

function timeAxis(plot, x0, nowMs, x) {
  const spanS = (nowMs - x0) / 1000;
  const step = TIME_STEPS_S.find((s) => spanS / s <= 6) ?? 3600;
  const g = svg('g', { class: 'axis' },
    svg('line', { x1: plot.left, x2: plot.right, y1: plot.bottom, y2: plot.bottom }));
  for (let back = 0; back <= spanS; back += step) {
    const text = back === 0 ? 'now' : back < 60 ? `−${back} s` : `−${back / 60} min`;
    g.append(svg('text', { x: x(nowMs - back * 1000), y: plot.bottom + 16, 'text-anchor': 'middle', text }));
  }
  return g;
}

function short(text) {
  return text.length > 28 ? `${text.slice(0, 27)}…` : text;
}
