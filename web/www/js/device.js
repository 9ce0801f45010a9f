// Device: the board's console over WebSerial (Chromium), or relayed by
// `polyturn web --board PORT` in any browser (relayport.js): status and
// the live phase error, the settings form checked by the sync core's own
// `set` (WebAssembly) before anything is sent, engage/stop/save, the
// encoder check, dividing (`divide.js`), the guided setup, and a cam table
// upload.
import { load, dl, shared } from './polyturn.js';
import { showDivide } from './divide.js';
import { Session, pairs } from './serial.js';
import { fakeSerialPort } from './fakeport.js';
import { relayPort, relayed } from './relayport.js';
import { draw, umPerStep } from './phaseplot.js';

// a sector erase takes up to 2 s (DS10314 t_ERASE128KB); `polyturn device`
// waits 10 s for it (FLASH_WAIT), and so does the page
const SAVE_WAIT_MS = 10000;
const PLOT_POINTS = 300; // 30 s of watch at 10 Hz
let session = null;
let settings = '';
let fields = null; // each setting's unit, range and choices, from the console (setting_fields)
let relay = null; // the relayed board's port, when connected through polyturn web
const phase = []; // {v: phase error in steps, state}

const $ = (id) => document.getElementById(id);

export function init() {
  const supported = 'serial' in navigator;
  $('serial-support').textContent = supported
    ? 'Connect the board by USB and choose its port (polyturn console).'
    : 'This browser has no WebSerial: use Chromium, Chrome or Edge, or serve the page with the board from the machine it is plugged into (`polyturn web --board PORT`): then any browser has it.';
  $('connect').disabled = !supported;
  $('connect').addEventListener('click', () => connect(() => navigator.serial.requestPort()));
  $('simulated').addEventListener('click', () => connect(fakeSerialPort));
  $('connect-relay').addEventListener('click', () => connect(() => relayPort({ onControl: controlChanged, onNotice: (why) => log(`relay: ${why}`) })));
  $('take-control').addEventListener('click', () => relay?.take());
  $('read-settings').addEventListener('click', () => refreshSettings().then(watch, () => {}));
  relayed().then((yes) => {
    if (!yes) return;
    $('connect-relay').hidden = false;
    $('serial-support').textContent = 'This page was served with the board: connect through polyturn web (any browser).';
  });
  $('engage').addEventListener('click', () => command('engage'));
  $('stop').addEventListener('click', () => command('stop'));
  $('clear').addEventListener('click', () => command('clear'));
  $('save').addEventListener('click', () => command('save', SAVE_WAIT_MS));
  $('check-start').addEventListener('click', () => command('check-encoder start', undefined, 'check-result'));
  $('check-stop').addEventListener('click', () => command('check-encoder stop', 5000, 'check-result'));
  $('divide-start').addEventListener('click', () => divide(`divide ${$('divide-n').value.trim()}`));
  $('divide-stop').addEventListener('click', () => divide('divide stop'));
  $('guided').addEventListener('submit', (e) => { e.preventDefault(); guided(); });
  $('guided').elements.cutter.addEventListener('change', showCutterFields);
  $('cam-upload').addEventListener('click', uploadCam);
}

async function connect(choose) {
  try {
    const port = await choose();
    session = await Session.open(port);
    session.onLine = onStatus;
    session.onClose = () => closed(port);
    const simulated = !!port.getInfo?.().simulated;
    relay = port.getInfo?.().relay ? port : null;
    for (const b of ['connect', 'simulated', 'connect-relay']) $(b).disabled = true;
    if (relay) {
      $('connect-relay').textContent = `Connected through polyturn web (${relay.name})`;
      controlChanged(relay.control);
      return;
    }
    commands(true);
    $('connect').textContent = simulated ? 'Connected to the simulated board' : 'Connected';
    if (simulated) simulatedLathe(port.board);
    await refreshSettings();
    await watch();
  } catch (e) {
    log(`connect: ${e.message ?? e}`);
    if (!session) $('connect-relay').disabled = false;
  }
}

// The buttons that send to the board.
function commands(on) {
  const keep = ['connect', 'simulated', 'connect-relay', 'take-control'];
  for (const b of document.querySelectorAll('#device button, #guided button')) if (!keep.includes(b.id)) b.disabled = !on;
}

// The relay's word on who has control: this page sends, or watches.
let inControl = false;
async function controlChanged(c) {
  if (!session || !relay || !c) return;
  const was = inControl;
  inControl = c.yours;
  const state = $('relay-state');
  state.hidden = false;
  state.textContent = c.yours ? 'This page has control of the board.'
    : c.free ? 'Nobody has control of the board: take it to send commands.'
      : 'Another page has control of the board; this one watches its status.';
  $('take-control').hidden = c.yours;
  $('take-control').disabled = !c.free;
  commands(c.yours);
  if (c.yours && !was) {
    try { await refreshSettings(); } catch { /* shown in the log */ }
    await watch();
  }
}

// The port closed: through the relay, the board went away (or polyturn
// web stopped); what waited for a reply has failed and nothing is sent
// again. Reconnect opens it anew.
function closed(port) {
  log('the port closed');
  session = null;
  commands(false);
  if (!port.getInfo?.().relay) {
    $('connect').textContent = 'Connect (WebSerial)';
    $('connect').disabled = !('serial' in navigator);
    return;
  }
  relay = null;
  inControl = false;
  const state = $('relay-state');
  state.hidden = false;
  const why = port.goneWhy || 'the board went away';
  state.textContent = `${why[0].toUpperCase()}${why.slice(1)}. Reconnect when it is back.`;
  $('take-control').hidden = true;
  $('connect-relay').textContent = 'Reconnect';
  $('connect-relay').disabled = false;
}

// The simulated board's lathe: a speed the machinist sets, as on the
// lathe's own control; the board sees it only through its encoder.
function simulatedLathe(board) {
  const input = $('sim-lathe-rpm');
  $('sim-lathe').hidden = false;
  input.addEventListener('change', () => {
    const rpm = Math.min(Math.max(Number(input.value) || 0, 0), Number(input.max));
    input.value = String(rpm);
    board.set_lathe_rpm(rpm);
    log(`(the simulated lathe set to ${rpm} rpm)`);
  });
  $('sim-hand').addEventListener('click', () => {
    const deg = Math.min(Math.max(Number($('sim-hand-deg').value) || 0, -3600), 3600);
    board.turn_by_hand(deg);
    log(`(a hand turns the simulated chuck by ${deg} degrees)`);
  });
}

function log(text) {
  const el = $('log');
  el.textContent = `${el.textContent}${text}\n`.split('\n').slice(-200).join('\n');
  el.scrollTop = el.scrollHeight;
}

// Any command stops `watch` on the board; it starts again once no
// command is waiting.
let inflight = 0;
async function ask(cmd, wait) {
  inflight++;
  log(`> ${cmd}`);
  try {
    const r = await session.ask(cmd, wait);
    log(r);
    return r;
  } catch (e) {
    log(e.message);
    throw e;
  } finally {
    inflight--;
    setTimeout(() => { if (inflight === 0) watch(); }, 0);
  }
}

async function watch() {
  try { await session.ask('watch'); } catch { /* the next command shows why */ }
}

// `divide N` or `divide stop`: the readout follows in the status lines;
// a refusal is shown in the board's words.
async function divide(cmd) {
  try {
    await ask(cmd);
    $('divide-error').textContent = '';
  } catch (e) {
    $('divide-error').textContent = e.message;
  }
}

async function command(cmd, wait, target) {
  const out = target ? $(target) : null;
  try {
    const r = await ask(cmd, wait);
    if (out) out.textContent = r;
  } catch (e) {
    if (out) out.textContent = e.message;
  }
  if (cmd === 'save' || cmd.startsWith('set')) await refreshSettings();
}

function onStatus(line) {
  if (!line.startsWith('ok state=')) return log(line);
  const s = pairs(line);
  dl($('status'), [
    ['state', s.state], ['fault', s.fault + (s.reason ? `: ${s.reason}` : '')],
    ['lathe', `${s.lathe_rpm} rpm`], ['cutter', `${s.cutter_rpm} rpm`],
    ['phase error', `${s.phase_err_steps} steps`], ['target / cutter', `${s.target} / ${s.cutter} steps`],
    ['index seen', s.indexed],
    ['spindle', `${s.angle_deg}° from ${s.angle_from === 'index' ? 'the index' : 'the start (no index yet)'}`],
  ]);
  $('status').dataset.state = s.state;
  $('status').dataset.json = JSON.stringify(s);
  showDivide(s);
  phase.push({ v: Number(s.phase_err_steps), state: s.state });
  if (phase.length > PLOT_POINTS) phase.shift();
  plot();
}

// The phase error over the last 30 s (phaseplot.js), with µm at the
// stock's radius from the board's steps and ratio and the page's R2.
function plot() {
  const set = pairs(settings);
  const r2 = Number(shared.setup.stockRadius);
  const umStep = umPerStep(set.steps, set.ratio, r2);
  const d = draw(phase, PLOT_POINTS, { umStep, r2 });
  const svg = $('phase-plot');
  svg.innerHTML = d.svg;
  Object.assign(svg.dataset, { span: d.span, clipped: d.clipped, worst: d.worst, steadyFrom: d.steadyFrom, umStep: umStep ?? '' });
}

// One row per `get` key: its name, a field (a select when the console
// takes only a few words), its unit, and Set.
async function refreshSettings() {
  settings = await ask('get');
  fields ??= JSON.parse((await load()).setting_fields());
  const rows = Object.entries(pairs(settings)).map(([name, value]) => settingRow(name, value, fields.find((f) => f.name === name)));
  $('settings').replaceChildren(...rows);
}

function settingRow(name, value, info) {
  const el = (tag, props) => Object.assign(document.createElement(tag), props);
  const row = el('div', { className: 'setting' });
  const label = el('label', { textContent: name, title: info?.allowed ?? '' });
  let input;
  if (info?.choices.length) {
    input = el('select', { name });
    input.append(...info.choices.map((c) => el('option', { value: c, textContent: c })));
  } else {
    input = el('input', { name, title: info?.allowed ?? '' });
    if (info?.min !== null && info?.min !== undefined) Object.assign(input, { type: 'number', step: 'any', min: info.min, max: info.max });
  }
  input.value = value;
  input.addEventListener('input', () => validate(input));
  label.htmlFor = input.id = `setting-${name}`;
  const unit = el('span', { className: 'unit', textContent: info?.unit ?? (info?.allowed.match(/\((.*)\)/)?.[1] ?? '') });
  const set = el('button', { type: 'button', textContent: 'Set' });
  set.dataset.name = name;
  set.addEventListener('click', () => setOne(input));
  row.append(label, input, unit, set);
  return row;
}

// The sync core's own `set`, on the board's settings, in WebAssembly.
async function validate(input) {
  const error = (await load()).check_setting(settings, input.name, input.value.trim());
  input.classList.toggle('bad', !!error);
  $('settings-error').textContent = error ?? '';
  return error;
}

async function setOne(input) {
  if (await validate(input)) return; // refused here: nothing is sent
  await command(`set ${input.name} ${input.value.trim()}`, undefined, 'settings-error');
}

// The guided setup's fields for what turns the cutter: a stepper's motor
// and driver, or a BLDC's encoder, full speed and drive (`--drive bldc`).
function showCutterFields() {
  const cutter = $('guided').elements.cutter.value;
  for (const label of document.querySelectorAll('#guided label[data-for]')) {
    const kind = label.dataset.for;
    label.hidden = !(kind === cutter || (kind === 'bldc' && cutter !== 'stepper'));
  }
}

// The flags `polyturn device setup` takes for the form's facts.
function guidedArgs(f) {
  const args = ['--encoder-lines', f.lines.value, '--max-lathe-rpm', f['max-rpm'].value];
  const cutter = f.cutter.value;
  if (cutter === 'stepper') {
    return args.concat(['--motor-steps', f['motor-steps'].value, '--microsteps', f.microsteps.value, '--reduction', f.reduction.value]);
  }
  args.push('--drive', 'bldc', '--bldc-out', cutter, '--cutter-encoder-cpr', f['cutter-cpr'].value, '--cutter-max-rpm', f['cutter-max-rpm'].value);
  if (cutter === 'pwm') args.push('--pwm-hz', f['pwm-hz'].value);
  if (Number(f['bldc-tau'].value) !== 0) args.push('--bldc-tau', f['bldc-tau'].value);
  return args;
}

async function guided() {
  const f = $('guided').elements;
  const args = guidedArgs(f);
  const out = $('guided-result');
  try {
    const plan = JSON.parse((await load()).guided_setup(args, settings));
    for (const [name, value] of plan.order) await ask(`set ${name} ${value}`);
    out.textContent = `${plan.summary}\nnot saved yet: Save to flash keeps them.`;
    await refreshSettings();
  } catch (e) {
    out.textContent = `error: ${e.message ?? e}`;
  }
}

async function uploadCam() {
  const file = $('cam-file').files[0];
  const out = $('cam-result');
  if (!file) { out.textContent = 'choose a table file first'; return; }
  try {
    settings = await ask('get'); // a compensating table goes only to its ratio and edges
    const lines = (await load()).cam_lines(file.name, await file.text(), settings);
    let last = '';
    for (const [i, line] of lines.entries()) {
      last = await ask(line, i + 1 === lines.length ? SAVE_WAIT_MS : undefined);
      out.textContent = `sent ${i + 1} of ${lines.length} lines`;
    }
    out.textContent = `uploaded ${lines.length} lines: ${last}`;
  } catch (e) {
    out.textContent = `error: ${e.message ?? e}`;
  }
}
