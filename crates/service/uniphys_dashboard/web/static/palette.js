/**
 * Distinct colours for the n-th part or series: hues a golden angle apart never repeat and stay
 * far from their neighbours, however many there are.
 */

const GOLDEN_ANGLE_DEG = 137.508;
const SATURATION = 0.62;
const LIGHTNESS = 0.52;

/** Hue of the n-th colour, in turns (0 ≤ hue < 1). */
export function hue(n) {
  return ((n * GOLDEN_ANGLE_DEG + 210) % 360) / 360;
}

/** The n-th colour as HSL fractions, for `THREE.Color.setHSL`. */
export function hsl(n) {
  return { h: hue(n), s: SATURATION, l: LIGHTNESS };
}

/** The n-th colour as CSS. */
export function css(n) {
  const { h, s, l } = hsl(n);
  return `hsl(${(h * 360).toFixed(1)} ${s * 100}% ${l * 100}%)`;
}
