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
  const label = () => {
    const s = shared.setup;
    document.getElementById('sim-setup').textContent =
      `setup: ratio ${s.ratio} × ${s.edges} edges, ${s.direction} sense, R1 ${s.cutterRadius} R2 ${s.stockRadius} DOC ${s.depth} mm (from Plan or Preview)`;
    form.elements.rpm.value = String(shared.rpm);
  };
  shared.listeners.push(label);
  label();
}

export function args(form) {
  const f = fields(form);
  return ['simulate', ...setupFlags(shared.setup), '--rpm', f.rpm, '--revolutions', f.revolutions,
    '--ripple', f.ripple, '--start', f.start, '--drive', f.drive, '--seed', f.seed, '--json', '--svg', 'sim.svg'];
}

function start(form) {
  worker ??= new Worker(new URL('./worker.js', import.meta.url), { type: 'module' });
  const status = document.getElementById('sim-status');
  const err = document.getElementById('sim-error');
  status.textContent = 'simulating in the background…';
  err.textContent = '';
  document.body.dataset.sim = 'running';
  const t0 = performance.now();
  worker.onmessage = (e) => {
    document.body.dataset.sim = e.data.ok ? 'done' : 'failed';
    if (!e.data.ok) {
      status.textContent = '';
      err.textContent = `error: ${e.data.error}`;
      return;
    }
    status.textContent = `simulated in ${((performance.now() - t0) / 1000).toFixed(1)} s`;
    const r = JSON.parse(e.data.out);
    const el = document.getElementById('sim-figures');
    el.dataset.json = e.data.out;
    dl(el, [
      ['sides cut', r.cut.sides],
      ['across flats', r.cut.across_flats === null ? 'n/a (odd sides)' : `${fixed(r.cut.across_flats, 4)} mm (ideal ${fixed(r.ideal.across_flats, 4)})`],
      ['worst phase error while synced', `${fixed(r.max_error_steps, 2)} steps (${fixed(r.max_error_deg, 4)}° of the work)`],
      ['worst while cutting', `${fixed(r.max_error_steps_cutting, 2)} steps`],
      ['worst section deviation', `${fixed(r.max_profile_deviation * 1000, 2)} µm`],
      ['final error at rest', `${r.final_error_steps} steps`],
      ['faults', r.faults.length ? r.faults.map((f) => `${f.kind} at tick ${f.tick}: ${f.reason}`).join('; ') : 'none'],
      ['steps / encoder counts', `${r.steps_emitted} / ${r.encoder_counts} in ${r.ticks} ticks`],
    ]);
    document.getElementById('sim-svg').innerHTML = e.data.svg;
  };
  worker.postMessage({ args: args(form) });
}
