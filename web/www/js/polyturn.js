// The host library in WebAssembly (web/src/lib.rs): every figure the page
// shows comes from here, the same code as the `polyturn` command line.
import init, * as wasm from '../pkg/polyturn_web.js';

let ready;
export function load() {
  ready ??= init().then(() => wasm);
  return ready;
}

// `polyturn <args>`: {out, files}; throws the CLI's one-line error.
export async function cli(args) {
  const w = await load();
  return JSON.parse(w.run(args.map(String)));
}

// `polyturn <args> --json`, parsed.
export async function cliJson(args) {
  return JSON.parse((await cli([...args, '--json'])).out);
}

// The six variables of a setup as the CLI's flags.
export function setupFlags(s) {
  return ['--cutter-radius', s.cutterRadius, '--stock-radius', s.stockRadius, '--depth', s.depth,
    '--ratio', s.ratio, '--edges', s.edges, '--direction', s.direction].map(String);
}

// The page's one setup, shared by Plan, Preview and Simulate.
export const shared = {
  setup: { cutterRadius: 50, stockRadius: 20, depth: 5, ratio: '2', edges: 3, direction: 'same' },
  rpm: 600,
  tolerance: 0.01,
  listeners: [],
  set(setup) {
    Object.assign(this.setup, setup);
    this.listeners.forEach((f) => f(this.setup));
  },
};

// A form's fields as {name: value}, empty ones left out.
export function fields(form) {
  const out = {};
  for (const el of form.elements) {
    if (el.name && el.value !== '') out[el.name] = el.value;
  }
  return out;
}

export function dl(el, rows) {
  el.replaceChildren(...rows.flatMap(([k, v]) => {
    const dt = document.createElement('dt');
    const dd = document.createElement('dd');
    dt.textContent = k;
    dd.textContent = v;
    return [dt, dd];
  }));
}

export const fixed = (v, p) => (v === null || v === undefined ? '–' : Number(v).toFixed(p));
