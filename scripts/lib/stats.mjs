/** Median of a list of numbers. */
export function median(xs) {
  const s = [...xs].sort((a, b) => a - b);
  return s[Math.floor(s.length / 2)];
}

/** Rounds to `d` decimals for printing. */
export const round = (x, d = 2) => Math.round(x * 10 ** d) / 10 ** d;
