// Device: the board's console over WebSerial (Chromium): status and the
// live phase error, the settings form checked by the sync core's own `set`
// (WebAssembly) before anything is sent, engage/stop/save, the encoder
// check, dividing (`divide.js`), the guided setup, and a cam table upload.
import { load, dl } from './polyturn.js';
import { showDivide } from './divide.js';
import { Session, pairs } from './serial.js';
import { fakeSerialPort } from './fakeport.js';

const SAVE_WAIT_MS = 5000; // a sector erase (DS10314 t_ERASE128KB) and more
const PLOT_POINTS = 300; // 30 s of watch at 10 Hz
let session = null;
let settings = '';
let fields = null; // each setting's unit, range and choices, from the console (setting_fields)
const phase = [];

const $ = (id) => document.getElementById(id);

export function init() {
  const supported = 'serial' in navigator;
  $('serial-support').textContent = supported
    ? 'Connect the board by USB and choose its port (polyturn console).'
    : 'This browser has no WebSerial: use Chromium, Chrome or Edge for the device panel (or `polyturn device`).';
  $('connect').disabled = !supported;
  $('connect').addEventListener('click', () => connect(() => navigator.serial.requestPort()));
  $('simulated').addEventListener('click', () => connect(fakeSerialPort));
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
    session.onClose = () => log('the port closed');
    for (const b of document.querySelectorAll('#device button, #guided button')) b.disabled = false;
    const simulated = !!port.getInfo?.().simulated;
    $('connect').textContent = simulated ? 'Connected to the simulated board' : 'Connected';
    if (simulated) simulatedLathe(port.board);
    $('connect').disabled = true;
    $('simulated').disabled = true;
    await refreshSettings();
    await watch();
  } catch (e) {
    log(`connect: ${e.message ?? e}`);
  }
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
  phase.push(Number(s.phase_err_steps));
  if (phase.length > PLOT_POINTS) phase.shift();
  plot();
}

// The phase error over the last 30 s, axes labelled in steps and seconds.
function plot() {
  const svg = $('phase-plot');
  const span = Math.max(0.5, ...phase.map(Math.abs));
  // room on the left for the widest label (11 px type: about 6.5 px a
  // character), so +9999.04 is not cut off at the edge
  const [w, h, bottom] = [420, 180, 30];
  const left = Math.max(50, 24 + 6.5 * `+${span.toFixed(2)}`.length);
  const x = (i) => left + ((w - left - 10) * i) / (PLOT_POINTS - 1);
  const y = (v) => (h - bottom) / 2 - ((h - bottom) / 2 - 8) * (v / span);
  const pts = phase.map((v, i) => `${x(i + PLOT_POINTS - phase.length).toFixed(1)},${y(v).toFixed(1)}`).join(' ');
  svg.innerHTML = `<line x1="${left}" y1="${y(0)}" x2="${w - 10}" y2="${y(0)}" stroke="#999"/>
    <line x1="${left}" y1="8" x2="${left}" y2="${h - bottom}" stroke="#333"/>
    <text x="${left - 4}" y="${y(span) + 4}" text-anchor="end" font-size="11">+${span.toFixed(2)}</text>
    <text x="${left - 4}" y="${y(-span) + 4}" text-anchor="end" font-size="11">-${span.toFixed(2)}</text>
    <text x="${left - 4}" y="${y(0) + 4}" text-anchor="end" font-size="11">0</text>
    <text x="14" y="${(h - bottom) / 2}" font-size="11" transform="rotate(-90 14 ${(h - bottom) / 2})" text-anchor="middle">phase error, steps</text>
    <text x="${left}" y="${h - 8}" font-size="11">−30 s</text><text x="${w - 10}" y="${h - 8}" font-size="11" text-anchor="end">now</text>
    <text x="${(w + left) / 2}" y="${h - 8}" font-size="11" text-anchor="middle">time</text>
    <polyline fill="none" stroke="#c33" stroke-width="1.5" points="${pts}"/>`;
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
    const lines = (await load()).cam_lines(file.name, await file.text());
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
