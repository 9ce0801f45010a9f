// Plan: the setups table, exactly `polyturn setups --json`.
import { cliJson, shared, fields, fixed } from './polyturn.js';

const FLAGS = ['sides', 'stock-radius', 'across-flats', 'depth', 'cutter-radius', 'rpm', 'tolerance', 'max-edges', 'max-ratio'];

export function init({ show }) {
  const form = document.getElementById('plan-form');
  form.addEventListener('submit', (e) => {
    e.preventDefault();
    run(form, show);
  });
  run(form, show);
}

async function run(form, show) {
  const f = fields(form);
  if (f.depth !== undefined) delete f['across-flats'];
  const args = ['setups', ...FLAGS.filter((k) => f[k] !== undefined).flatMap((k) => [`--${k}`, f[k]])];
  const err = document.getElementById('plan-error');
  const body = document.querySelector('#setups tbody');
  try {
    const r = await cliJson(args);
    err.textContent = r.setups.length ? '' : 'no setup cuts this within the limits';
    body.replaceChildren(...r.setups.map((s) => row(s, r, f, show)));
    notes(r);
  } catch (e) {
    err.textContent = `error: ${e}`;
    body.replaceChildren();
    notes(null);
  }
}

// What the planner assumed and warns of, as `polyturn setups` prints them:
// the cutter radius (and why, when it was not given), each note (the "–"),
// each warning, and the command lines that reproduce the first row.
function notes(r) {
  const box = document.getElementById('plan-notes');
  if (!r) return box.replaceChildren();
  const p = (text, cls) => {
    const e = document.createElement('p');
    e.textContent = text;
    if (cls) e.className = cls;
    return e;
  };
  const radius = `Cutter radius R1: ${fixed(r.cutter_radius, 1)} mm` +
    (r.cutter_radius_assumed ? `, assumed: ${r.cutter_radius_assumed}` : ', as given');
  box.replaceChildren(p(radius), ...r.notes.map((n) => p(`note: ${n}`)),
    ...r.warnings.map((w) => p(`warning: ${w}`, 'warning')),
    ...(r.setups.length ? [p(`first row: ${r.geometry_command}`, 'hint'), p(`simulate it: ${r.simulate_command}`, 'hint')] : []));
}

function row(s, r, f, show) {
  const tr = document.createElement('tr');
  const cells = [s.ratio, s.edges, s.direction, s.revolutions, fixed(s.flat_deviation, 4),
    s.corners_sharp ? 'sharp' : 'round', fixed(s.cutter_rpm, 0), fixed(s.peak_tip_speed, 2), s.min_cutter_radius ?? '–',
    s.warnings.join('; ')];
  tr.replaceChildren(...cells.map((c) => {
    const td = document.createElement('td');
    td.textContent = c;
    return td;
  }));
  tr.addEventListener('click', () => {
    for (const o of tr.parentElement.children) o.classList.toggle('selected', o === tr);
    shared.rpm = Number(f.rpm ?? shared.rpm);
    shared.tolerance = Number(f.tolerance ?? shared.tolerance);
    shared.set({ cutterRadius: r.cutter_radius, stockRadius: Number(f['stock-radius']), depth: r.depth,
      ratio: s.ratio, edges: s.edges, direction: s.direction });
    show('preview');
  });
  return tr;
}
