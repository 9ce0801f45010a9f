// Simulate: `polyturn simulate --json --svg` in a Web Worker; the section
// against the ideal and the phase error over time (the simulator's SVG).
import { shared, setupFlags, fields, dl, fixed } from './polyturn.js';

let worker;

export function init() {
  const form = document.getElementById('sim-form');
  form.addEventListener('submit', (e) => {
    e.preventDefault();
    start(form);
  });
  form.elements.drive.addEventListener('change', () => {
    document.getElementById('sim-bldc-out').hidden = form.elements.drive.value !== 'bldc';
  });
  const label = () => {
    const s = shared.setup;
    document.getElementById('sim-setup').textContent =
      `setup: ratio ${s.ratio}, ${s.edges} edges, ${s.direction} sense, cutter radius R1 ${s.cutterRadius} mm, stock radius R2 ${s.stockRadius} mm, depth of cut ${s.depth} mm (from Plan or Preview)`;
    form.elements.rpm.value = String(shared.rpm);
  };
  shared.listeners.push(label);
  label();
}

export function args(form) {
  const f = fields(form);
  // a BLDC's drive (`--bldc-out`), asked only for a BLDC: the page offers
  // the one that holds phase first, a spindle driver's speed input
  const bldc = f.drive === 'bldc' ? ['--bldc-out', f['bldc-out']] : [];
  return ['simulate', ...setupFlags(shared.setup), '--rpm', f.rpm, '--revolutions', f.revolutions,
    '--ripple', f.ripple, '--start', f.start, '--encoder-cpr', f['encoder-cpr'], '--motor-steps', f['motor-steps'],
    '--drive', f.drive, ...bldc, '--seed', f.seed, '--json', '--svg', 'sim.svg'];
}

function start(form) {
  worker ??= new Worker(new URL('./worker.js', import.meta.url), { type: 'module' });
  const status = document.getElementById('sim-status');
  const err = document.getElementById('sim-error');
  status.textContent = 'simulating in the background…';
  err.textContent = '';
  document.body.dataset.sim = 'running';
  worker.onmessage = (e) => {
    document.body.dataset.sim = e.data.ok ? 'done' : 'failed';
    if (!e.data.ok) {
      status.textContent = '';
      err.textContent = `error: ${e.data.error}`;
      return;
    }
    const r = JSON.parse(e.data.out);
    const hz = r.tick_hz; // the control tick `polyturn simulate` ran, the board's
    status.textContent = `done: ${form.elements.revolutions.value} lathe turns at ${form.elements.rpm.value} rpm`;
    const el = document.getElementById('sim-figures');
    el.dataset.json = e.data.out;
    dl(el, [
      ['sides cut', r.cut.sides],
      ['across flats', r.cut.across_flats === null ? 'n/a (odd sides)' : `${fixed(r.cut.across_flats, 4)} mm (ideal ${fixed(r.ideal.across_flats, 4)})`],
      ['worst phase error while synced', `${fixed(r.max_error_steps, 2)} steps (${fixed(r.max_error_deg, 4)}° of the work)`],
      ['worst while cutting', `${fixed(r.max_error_steps_cutting, 2)} steps`],
      ['worst section deviation', `${fixed(r.max_profile_deviation * 1000, 2)} µm`],
      ['final error at rest', `${r.final_error_steps} steps`],
      ['faults', r.faults.length ? r.faults.map((f) => `${f.kind} at ${fixed(f.tick / hz, 3)} s: ${f.reason}`).join('; ') : 'none'],
      ['motor steps / encoder counts', `${r.steps_emitted} steps / ${r.encoder_counts} counts in ${fixed(r.ticks / hz, 2)} s`],
    ]);
    document.getElementById('sim-svg').innerHTML = e.data.svg;
    document.getElementById('sim-explain').hidden = false;
  };
  worker.postMessage({ args: args(form) });
}
