// The Device view's phase error chart. Its scale is set by the error while
// synced, what the machinist reads, not by the engage transient (the
// catch-up from rest reads thousands of steps): the transient's span is
// shaded, and a value past the scale is drawn at its edge with a marker
// and the largest one written beside it. The scale goes in 1-2-5 steps;
// the right axis gives the same error as µm at the work: the arc the
// cutter's phase moves the section by at the stock's radius R2,
// steps / steps-per-cutter-turn × 360° / GR of the work's angle.

const [W, H, TOP, BOTTOM, LEFT, RIGHT] = [520, 200, 22, 30, 58, 70];

// The smallest of 1, 2, 5 × 10^k at least `v` (0.5 at the least).
export function niceSpan(v) {
  const m = Math.max(Math.abs(v), 0.5);
  const p = 10 ** Math.floor(Math.log10(m));
  for (const f of [1, 2, 5, 10]) if (f * p >= m - 1e-9) return f * p;
  return 10 * p;
}

// µm at the work per step of the cutter: R2 × 2π / (steps × GR) mm.
export function umPerStep(steps, ratio, r2) {
  const [a, b = '1'] = String(ratio ?? '').split(/[/:]/);
  const gr = Number(a) / Number(b);
  const s = Number(steps);
  if (!(gr > 0 && s > 0 && r2 > 0)) return null;
  return (1000 * r2 * 2 * Math.PI) / (s * gr);
}

const fmt = (v) => (Math.abs(v) >= 100 ? v.toFixed(0) : Math.abs(v) >= 10 ? v.toFixed(1) : v.toFixed(2));
const signed = (v) => `${v > 0 ? '+' : v < 0 ? '−' : ''}${fmt(Math.abs(v))}`;

// samples: [{v: steps, state}], oldest first, `points` wide. Returns the
// SVG's inner markup and what it shows (for the page's tests).
export function draw(samples, points, { umStep = null, r2 = null } = {}) {
  const synced = samples.filter((s) => s.state === 'synced').map((s) => s.v);
  const steady = synced.length ? synced : samples.map((s) => s.v);
  const span = niceSpan(Math.max(0, ...steady.map(Math.abs)));
  const x = (i) => LEFT + ((W - LEFT - RIGHT) * (i + points - samples.length)) / (points - 1);
  const y = (v) => TOP + ((H - TOP - BOTTOM) / 2) * (1 - Math.max(-1, Math.min(1, v / span)));
  const parts = [];
  // the transient's span, shaded: every run of samples not synced once
  // the board had been asked to engage (state engaging)
  for (let i = 0; i < samples.length; i++) {
    if (samples[i].state !== 'engaging') continue;
    let j = i;
    while (j + 1 < samples.length && samples[j + 1].state === 'engaging') j++;
    parts.push(`<rect class="transient" x="${x(i).toFixed(1)}" y="${TOP}" width="${Math.max(2, x(j) - x(i)).toFixed(1)}" height="${H - TOP - BOTTOM}" fill="#f4e3b5"/>`);
    if (x(j) - x(i) > 50) parts.push(`<text x="${((x(i) + x(j)) / 2).toFixed(1)}" y="${H - BOTTOM - 4}" font-size="10" text-anchor="middle" fill="#865">engaging</text>`);
    i = j;
  }
  const ticks = [-1, -0.5, 0, 0.5, 1].map((f) => f * span);
  for (const t of ticks) {
    parts.push(`<line x1="${LEFT}" y1="${y(t)}" x2="${W - RIGHT}" y2="${y(t)}" stroke="${t === 0 ? '#999' : '#e4e4e4'}"/>`);
    parts.push(`<text x="${LEFT - 4}" y="${y(t) + 4}" text-anchor="end" font-size="11">${signed(t)}</text>`);
    if (umStep) parts.push(`<text x="${W - RIGHT + 4}" y="${y(t) + 4}" font-size="11">${signed(t * umStep)}</text>`);
  }
  const pts = samples.map((s, i) => `${x(i).toFixed(1)},${y(s.v).toFixed(1)}`).join(' ');
  parts.push(`<polyline fill="none" stroke="#c33" stroke-width="1.5" points="${pts}"/>`);
  // past the scale: a marker at the edge, and the largest beyond it
  const clipped = samples.map((s, i) => ({ ...s, i })).filter((s) => Math.abs(s.v) > span);
  for (const s of clipped) {
    const up = s.v > 0;
    const [cx, cy] = [x(s.i), up ? TOP : H - BOTTOM];
    parts.push(`<path class="clipped" d="M${(cx - 3).toFixed(1)},${cy + (up ? 5 : -5)} L${cx.toFixed(1)},${cy} L${(cx + 3).toFixed(1)},${cy + (up ? 5 : -5)} Z" fill="#c33"/>`);
  }
  const worst = clipped.reduce((m, s) => (Math.abs(s.v) > Math.abs(m) ? s.v : m), 0);
  if (clipped.length) parts.push(`<text x="${W - RIGHT}" y="${TOP - 8}" text-anchor="end" font-size="11" fill="#c33">▲▼ past the scale, up to ${signed(worst)} steps (engaging)</text>`);
  parts.push(`<line x1="${LEFT}" y1="${TOP}" x2="${LEFT}" y2="${H - BOTTOM}" stroke="#333"/>`);
  parts.push(`<text x="12" y="${(H - BOTTOM + TOP) / 2}" font-size="11" transform="rotate(-90 12 ${(H - BOTTOM + TOP) / 2})" text-anchor="middle">steps</text>`);
  if (umStep) {
    parts.push(`<line x1="${W - RIGHT}" y1="${TOP}" x2="${W - RIGHT}" y2="${H - BOTTOM}" stroke="#333"/>`);
    const mid = (H - BOTTOM + TOP) / 2;
    parts.push(`<text x="${W - 12}" y="${mid}" font-size="11" transform="rotate(90 ${W - 12} ${mid})" text-anchor="middle">µm at R2 ${Number(r2.toFixed(3))} mm</text>`);
  }
  parts.push(`<text x="${LEFT}" y="${H - 8}" font-size="11">−30 s</text><text x="${W - RIGHT}" y="${H - 8}" font-size="11" text-anchor="end">now</text>`);
  parts.push(`<text x="${(W + LEFT - RIGHT) / 2}" y="${H - 8}" font-size="11" text-anchor="middle">time</text>`);
  return { svg: parts.join('\n'), span, clipped: clipped.length, worst, steadyFrom: synced.length ? 'synced' : 'all' };
}

export const SIZE = { width: W, height: H };
