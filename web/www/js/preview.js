// Preview: the section and the tip traces (`polyturn geometry --svg`),
// redrawn as the sliders move, with the figures of `geometry --json` and
// the smallest cutter for the tolerance (`setups`' min R1).
import { cli, cliJson, shared, setupFlags, fields, dl, fixed } from './polyturn.js';

let lastSvg = '';
let pending = false;

export function init() {
  const form = document.getElementById('preview-form');
  form.addEventListener('input', () => {
    Object.assign(shared.setup, fromForm(form));
    schedule(form);
  });
  form.addEventListener('change', () => smallestCutter(form));
  shared.listeners.push(() => {
    toForm(form, shared.setup);
    schedule(form);
    smallestCutter(form);
  });
  document.getElementById('export-svg').addEventListener('click', exportSvg);
  toForm(form, shared.setup);
  schedule(form);
  smallestCutter(form);
}

function fromForm(form) {
  const f = fields(form);
  return { cutterRadius: Number(f['cutter-radius']), stockRadius: Number(f['stock-radius']), depth: Number(f.depth),
    ratio: f.ratio, edges: Number(f.edges), direction: f.direction };
}

function toForm(form, s) {
  const set = (name, v) => {
    const el = form.elements[name];
    if (el.type === 'range' && Number(v) > Number(el.max)) el.max = String(Math.ceil(Number(v) * 2));
    el.value = String(v);
  };
  set('cutter-radius', s.cutterRadius);
  set('stock-radius', s.stockRadius);
  set('depth', s.depth);
  set('ratio', s.ratio);
  set('edges', s.edges);
  set('direction', s.direction);
  form.elements.tolerance.value = String(shared.tolerance);
}

// One redraw per frame, however fast the slider moves.
function schedule(form) {
  if (pending) return;
  pending = true;
  requestAnimationFrame(() => {
    pending = false;
    redraw(form);
  });
}

async function redraw(form) {
  for (const out of form.querySelectorAll('output')) out.textContent = out.closest('label').querySelector('input').value;
  const t0 = performance.now();
  const err = document.getElementById('preview-error');
  try {
    const r = await cli(['geometry', ...setupFlags(shared.setup), '--json', '--svg', 'section.svg']);
    const g = JSON.parse(r.out);
    lastSvg = r.files['section.svg'];
    document.getElementById('section-svg').innerHTML = lastSvg;
    err.textContent = '';
    figures(g);
  } catch (e) {
    err.textContent = `error: ${e}`;
  }
  // for the tests' timing only: a machinist has no use for it on screen
  document.body.dataset.redrawMs = (performance.now() - t0).toFixed(2);
}

function figures(g) {
  const el = document.getElementById('figures');
  const keep = el.querySelector('[data-min-r1]')?.textContent ?? '…';
  dl(el, [
    ['sides', `${g.sides} over ${g.revolutions} lathe turn(s)`],
    ['across flats', g.across_flats === null ? 'n/a (odd sides)' : `${fixed(g.across_flats, 4)} mm`],
    ['inscribed / circumscribed', `${fixed(g.inscribed_radius, 4)} / ${fixed(g.circumscribed_radius, 4)} mm`],
    ['flat deviation', `${g.flat_deviation >= 0 ? '+' : ''}${fixed(g.flat_deviation, 4)} mm (${g.flat_deviation >= 0 ? 'convex' : 'concave'})`],
    ['corners', g.corners_sharp ? 'sharp' : 'left round (stock at the corners)'],
    ['centre distance', `${fixed(g.centre_distance, 3)} mm`],
    ['smallest R1 for the tolerance', keep],
  ]);
  el.lastElementChild.dataset.minR1 = '';
  el.dataset.json = JSON.stringify(g);
}

// The planner's smallest cutter for this setup's ratio, edges and sense.
async function smallestCutter(form) {
  const s = shared.setup;
  shared.tolerance = Number(form.elements.tolerance.value) || shared.tolerance;
  let text;
  try {
    const g = await cliJson(['geometry', ...setupFlags(s)]);
    const r = await cliJson(['setups', '--sides', g.sides, '--stock-radius', s.stockRadius, '--depth', s.depth,
      '--tolerance', shared.tolerance, '--max-edges', 12, '--max-revolutions', 12,
      '--max-ratio', Math.ceil(Number(eval_ratio(g.ratio))) + 1]);
    const row = r.setups.find((x) => x.ratio === g.ratio && x.edges === g.edges && x.direction === g.direction);
    text = row?.min_cutter_radius ? `${row.min_cutter_radius} mm for ${shared.tolerance} mm` : 'no cutter within range';
  } catch (e) {
    text = '–';
  }
  const dd = document.querySelector('#figures [data-min-r1]');
  if (dd) dd.textContent = text;
}

function eval_ratio(r) {
  const [n, d] = String(r).split('/');
  return Number(n) / Number(d ?? 1);
}

function exportSvg() {
  const a = document.createElement('a');
  a.href = URL.createObjectURL(new Blob([lastSvg], { type: 'image/svg+xml' }));
  a.download = 'polyturn-section.svg';
  a.click();
  URL.revokeObjectURL(a.href);
}
