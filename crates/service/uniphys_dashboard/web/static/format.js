/**
 * Turning numbers from the API (SI units, Unix milliseconds, radians) into display text. Every
 * function answers "—" for a missing value.
 */

const NONE = '—';

const missing = (x) => x === null || x === undefined || Number.isNaN(x);

/** A count with thousands separators: `12,345`. */
export function count(n) {
  return missing(n) ? NONE : Number(n).toLocaleString('en-US');
}

/** A number with `digits` significant digits, without exponent for everyday magnitudes. */
export function num(x, digits = 3) {
  if (missing(x)) return NONE;
  if (x === 0) return '0';
  const magnitude = Math.abs(x);
  if (magnitude >= 1e6 || magnitude < 1e-3) return x.toExponential(digits - 1);
  return Number(x.toPrecision(digits)).toLocaleString('en-US', { maximumFractionDigits: 6 });
}

/** A fixed-point number: `0.648`. Negative zero prints as `0.000`. */
export function fixed(x, decimals = 3) {
  if (missing(x)) return NONE;
  const text = x.toFixed(decimals);
  return Number(text) === 0 ? (0).toFixed(decimals) : text;
}

/** A 3-vector: `(0.003, −1.000, 0.004)`. */
export function vec3(v, decimals = 3) {
  if (!Array.isArray(v)) return NONE;
  return `(${v.map((x) => fixed(x, decimals).replace('-', '−')).join(', ')})`;
}

/** Bytes in SI multiples: `1.2 MB`. */
export function bytes(n) {
  if (missing(n)) return NONE;
  const units = ['B', 'kB', 'MB', 'GB', 'TB'];
  let value = n;
  let unit = 0;
  while (value >= 1000 && unit < units.length - 1) {
    value /= 1000;
    unit += 1;
  }
  return unit === 0 ? `${n} B` : `${num(value, 3)} ${units[unit]}`;
}

/** A duration in milliseconds: `850 ms`, `2.4 s`, `3 min 05 s`, `2 h 07 min`. */
export function duration(ms) {
  if (missing(ms)) return NONE;
  if (ms < 1000) return `${Math.round(ms)} ms`;
  const s = ms / 1000;
  if (s < 60) return `${num(s, s < 10 ? 2 : 3)} s`;
  const whole = Math.round(s);
  if (whole < 3600) return `${Math.floor(whole / 60)} min ${pad2(whole % 60)} s`;
  return `${Math.floor(whole / 3600)} h ${pad2(Math.floor((whole % 3600) / 60))} min`;
}

/** Time since `atMs` until `nowMs`, rounded to seconds: `12 s ago`. */
export function ago(atMs, nowMs = Date.now()) {
  if (missing(atMs)) return NONE;
  const s = Math.max(0, Math.round((nowMs - atMs) / 1000));
  return s < 60 ? `${s} s ago` : `${duration(s * 1000)} ago`;
}

/** A Unix millisecond time as local `2026-11-25 12:55:03`. */
export function time(ms) {
  if (missing(ms)) return NONE;
  const d = new Date(ms);
  const date = `${d.getFullYear()}-${pad2(d.getMonth() + 1)}-${pad2(d.getDate())}`;
  return `${date} ${pad2(d.getHours())}:${pad2(d.getMinutes())}:${pad2(d.getSeconds())}`;
}

/** Radians shown in degrees: `90°`. */
export function degrees(rad) {
  return missing(rad) ? NONE : `${num((rad * 180) / Math.PI, 4)}°`;
}

/** Metres shown in millimetres: `337.6 mm`. */
export function millimetres(m) {
  return missing(m) ? NONE : `${num(m * 1000, 4)} mm`;
}

/** Kilograms: `32.4 kg`, `265 g`. */
export function mass(kg) {
  if (missing(kg)) return NONE;
  return kg < 1 ? `${num(kg * 1000, 3)} g` : `${num(kg, 3)} kg`;
}

/** A fraction 0…1 as a percentage: `42 %`. */
export function percent(fraction) {
  return missing(fraction) ? NONE : `${Math.round(fraction * 100)} %`;
}

function pad2(n) {
  return String(n).padStart(2, '0');
}
