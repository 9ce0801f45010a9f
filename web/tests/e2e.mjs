// The page in headless Chromium (Debian's), driven by playwright-core: it
// loads without console errors; its planner, preview and simulation give
// what the `polyturn` command line gives; its device panel works against
// the real sync core's console behind a fake WebSerial port; its DfuSe
// layer flashes and verifies a fake ROM bootloader. `node e2e.mjs`, after
// `bash web/build` and `cargo build -p polyturn-host`. SCREENSHOTS=dir
// also saves the views as PNGs (the book's are docs/src/web-*.png); each
// view's screenshot is taken and checked either way (`view`). WWW=dir
// serves another page folder (an older page, to show a check fails on it).
import { chromium } from 'playwright-core';
import { spawn, spawnSync, execFileSync } from 'node:child_process';
import { mkdtempSync, writeFileSync, readFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import assert from 'node:assert/strict';

const ROOT = new URL('../..', import.meta.url).pathname;
const POLYTURN = process.env.POLYTURN ?? join(ROOT, 'target/debug/polyturn');
const SHOTS = process.env.SCREENSHOTS;
const TMP = mkdtempSync(join(tmpdir(), 'polyturn-web-'));
const cli = (...args) => JSON.parse(execFileSync(POLYTURN, [...args.map(String), '--json'], { encoding: 'utf8' }));
const close = (a, b, what) => assert.ok(Math.abs(a - b) <= 1e-9 * Math.max(1, Math.abs(b)), `${what}: page ${a}, CLI ${b}`);

const server = spawn(POLYTURN, ['web', '--no-open', '--port', '0', '--dir', process.env.WWW ?? join(ROOT, 'web/www')]);
const url = await new Promise((resolve, reject) => {
  server.stdout.on('data', (d) => { const m = /http:\/\/\S+/.exec(String(d)); if (m) resolve(m[0]); });
  server.on('exit', (c) => reject(new Error(`polyturn web exited ${c}`)));
  setTimeout(() => reject(new Error('polyturn web printed no address in 10 s')), 10000);
});
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
  args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking',
    '--disable-component-update', '--disable-sync'],
});
const page = await browser.newPage({ viewport: { width: 1280, height: 900 }, acceptDownloads: true });
const errors = [];
page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
page.on('pageerror', (e) => errors.push(String(e)));
// WebSerial's port chooser, answered with the real console (fakeport.js)
await page.addInitScript(() => {
  Object.defineProperty(navigator, 'serial', {
    configurable: true,
    value: { requestPort: async () => { const port = await (await import('/js/fakeport.js')).fakeSerialPort(); window.testBoard = port.board; return port; } },
  });
});

const results = [];
async function test(name, f) {
  const t0 = Date.now();
  try {
    await f();
    results.push([name, 'ok']);
    console.log(`ok   ${name} (${Date.now() - t0} ms)`);
  } catch (e) {
    results.push([name, 'FAILED']);
    const log = await page.textContent('#log').catch(() => '');
    console.log(`FAIL ${name}\n     ${String(e.stack ?? e).split("\n").slice(0, 24).join('\n     ')}\n     console log: ${log.split('\n').slice(-10).join(' | ')}`);
  }
}
// A view as a machinist sees it at 1280 x 900: screenshotted (saved with
// SCREENSHOTS=dir as web-<shot>.png, from its top or scrolled to `at`), its
// title whole, nothing wider than the window, each of its main elements
// shown with a real size, and every line of text in its drawings inside
// the drawing (measured by the browser, not guessed).
async function view(name, mains, { shot = name, at = null } = {}) {
  await page.evaluate((at) => (at ? document.querySelector(at).scrollIntoView() : window.scrollTo(0, 0)), at);
  const png = await page.screenshot({ fullPage: false, ...(SHOTS ? { path: join(SHOTS, `web-${shot}.png`) } : {}) });
  assert.ok(png.length > 20000, `the ${name} screenshot is near blank (${png.length} bytes)`);
  const r = await page.evaluate(({ name, mains }) => {
    const box = (el) => { const b = el.getBoundingClientRect(); return { x: b.x, y: b.y, w: b.width, h: b.height, right: b.right }; };
    const section = document.getElementById(name);
    const h2 = section.querySelector('h2');
    const shown = (sel) => {
      const el = section.querySelector(sel);
      if (!el) return { sel, missing: true };
      const cs = getComputedStyle(el);
      return { sel, ...box(el), hidden: cs.display === 'none' || cs.visibility === 'hidden' || el.closest('[hidden]') !== null };
    };
    const texts = [...section.querySelectorAll('svg text')].map((t) => {
      const svg = t.ownerSVGElement.getBoundingClientRect();
      const b = t.getBoundingClientRect();
      return { text: t.textContent, over: b.right - svg.right, left: svg.left - b.left };
    });
    // a unit that runs out of its field's cell, under the next one
    const spilt = [...section.querySelectorAll('label .unit')].filter((u) => u.offsetParent !== null)
      .map((u) => ({ unit: u.textContent, over: u.getBoundingClientRect().right - u.closest('label').getBoundingClientRect().right }))
      .filter((u) => u.over > 1);
    return {
      spilt,
      active: section.classList.contains('active'),
      h2: { ...box(h2), clipped: h2.scrollWidth > h2.clientWidth, text: h2.textContent },
      pageWidth: document.documentElement.scrollWidth,
      mains: mains.map(shown),
      texts,
    };
  }, { name, mains });
  assert.ok(r.active, `${name} is the view shown`);
  assert.ok(r.h2.w > 100 && r.h2.h > 10 && r.h2.x >= 0 && r.h2.right <= 1280 && !r.h2.clipped, `${name}'s title is whole: ${JSON.stringify(r.h2)}`);
  assert.deepEqual(r.spilt, [], `${name}: units running out of their fields`);
  assert.ok(r.pageWidth <= 1280, `${name}: the page is ${r.pageWidth} px wide, wider than the window`);
  for (const m of r.mains) {
    assert.ok(!m.missing && !m.hidden && m.w >= 40 && m.h >= 15 && m.right <= 1281, `${name}: ${m.sel} is not shown whole: ${JSON.stringify(m)}`);
  }
  for (const t of r.texts) assert.ok(t.over <= 1 && t.left <= 1, `${name}: the drawing's text '${t.text}' runs ${Math.max(t.over, t.left).toFixed(0)} px past its edge`);
}
// Every field that takes a number or text, in `scope`, with the unit shown
// next to it (`.unit`); the names of those without one.
const unitless = (scope) => page.$$eval(`${scope} input:not([type=file]):not([type=hidden])`, (els) =>
  els.filter((el) => !(el.closest('label, .setting')?.querySelector('.unit')?.textContent.trim())).map((el) => el.name || el.id));
// Words a machinist should not meet: another spelling of µm, the page's
// own timings, the drawing's gain as a bare "x131".
async function noDeveloperText(name) {
  const text = await page.$eval(`#${name}`, (el) => el.textContent);
  for (const [bad, what] of [[/\bum\b/, '"um" for µm'], [/redrawn in|simulated in [\d.]+ ?m?s/, 'a timing'], [/deviation x\d/, 'a bare magnification']]) {
    assert.ok(!bad.test(text), `${name} shows ${what}: ${text.match(bad)?.[0]}`);
  }
}
const tab = (name) => page.click(`nav button[data-tab=${name}]`);
const setValue = (sel, v) => page.$eval(sel, (el, v) => { el.value = v; el.dispatchEvent(new Event('input', { bubbles: true })); el.dispatchEvent(new Event('change', { bubbles: true })); }, String(v));

const loaded = [];
page.on('requestfinished', (r) => loaded.push(r.url().split('/').pop()));
page.on('requestfailed', (r) => loaded.push(`FAILED ${r.url()} ${r.failure()?.errorText}`));
await page.goto(url, { timeout: 60000 }).catch((e) => { console.log(`the page did not load: ${loaded.join(' ')}`); throw e; });
await page.waitForSelector('body[data-ready=yes]', { timeout: 30000 });

let chosen;
await test('the planner table is polyturn setups --json', async () => {
  await page.fill('#plan-form [name=sides]', '6');
  await page.fill('#plan-form [name=stock-radius]', '20');
  await page.fill('#plan-form [name=across-flats]', '30');
  await page.fill('#plan-form [name=rpm]', '600');
  await page.click('#plan-form button[type=submit]');
  const want = cli('setups', '--sides', 6, '--stock-radius', 20, '--across-flats', 30, '--rpm', 600, '--tolerance', 0.01, '--max-edges', 6, '--max-ratio', 8);
  await page.waitForFunction((n) => document.querySelectorAll('#setups tbody tr').length === n, want.setups.length);
  const rows = await page.$$eval('#setups tbody tr', (trs) => trs.map((tr) => [...tr.children].map((td) => td.textContent)));
  assert.ok(want.setups.length >= 3, 'a hexagon has several setups');
  want.setups.forEach((s, i) => {
    assert.deepEqual(rows[i].slice(0, 5), [s.ratio, String(s.edges), s.direction, String(s.revolutions), s.flat_deviation.toFixed(4)], `row ${i}`);
    assert.equal(rows[i][8], s.min_cutter_radius === null ? '–' : String(s.min_cutter_radius), `row ${i} smallest R1, as setups gives it`);
  });
  chosen = { ...want.setups[0], cutter_radius: want.cutter_radius, stock: 20 };
  await view('plan', ['#plan-form', '#setups tbody tr']);
});

await test('the planner says the cutter radius it assumed, its notes and its warnings, beside the rows', async () => {
  await page.fill('#plan-form [name=rpm]', '3000');
  await page.click('#plan-form button[type=submit]');
  const want = cli('setups', '--sides', 6, '--stock-radius', 20, '--across-flats', 30, '--rpm', 3000, '--tolerance', 0.01, '--max-edges', 6, '--max-ratio', 8);
  assert.ok(want.warnings.length > 0 && want.cutter_radius_assumed, 'at 3000 rpm with no cutter given, the CLI warns and assumes');
  await page.waitForFunction(() => document.querySelectorAll('#plan-notes .warning').length > 0);
  const text = await page.$eval('#plan-notes', (e) => e.textContent);
  assert.ok(text.includes(`assumed: ${want.cutter_radius_assumed}`), text);
  for (const w of want.warnings) assert.ok(text.includes(`warning: ${w}`), `missing warning: ${w}`);
  for (const n of want.notes) assert.ok(text.includes(`note: ${n}`), `missing note: ${n}`);
  assert.ok(text.includes(want.geometry_command), 'the first row\'s geometry line');
  const cells = await page.$$eval('#setups tbody tr', (trs) => trs.map((tr) => tr.children[9].textContent));
  want.setups.forEach((s, i) => assert.equal(cells[i], s.warnings.join('; '), `row ${i} warnings`));
  await page.fill('#plan-form [name=rpm]', '600');
  await page.click('#plan-form button[type=submit]');
  await page.waitForFunction(() => !document.getElementById('plan-notes').textContent.includes('--rpm 3000'));
});

const geometry = (s) => cli('geometry', '--cutter-radius', s.cutter_radius, '--stock-radius', s.stock, '--depth', s.depth, '--ratio', s.ratio, '--edges', s.edges, '--direction', s.direction);
const previewJson = () => page.$eval('#figures', (el) => JSON.parse(el.dataset.json ?? 'null'));

await test('a chosen setup previews with the figures of polyturn geometry --json', async () => {
  await page.click('#setups tbody tr:first-child');
  await page.waitForSelector('#preview.tab.active');
  await page.waitForFunction((d) => JSON.parse(document.querySelector('#figures').dataset.json ?? 'null')?.depth === d, chosen.depth);
  assert.deepEqual(await previewJson(), geometry(chosen));
  const af = await page.textContent('#figures dd:nth-of-type(2)');
  assert.equal(af, `${geometry(chosen).across_flats.toFixed(4)} mm`);
  assert.ok(await page.$('#section-svg svg path'), 'the section is drawn');
  await page.waitForFunction(() => /^\d/.test(document.querySelector('[data-min-r1]')?.textContent ?? ''));
  assert.equal(await page.textContent('[data-min-r1]'), `${chosen.min_cutter_radius} mm for 0.01 mm`);
  await view('preview', ['#preview-form', '#figures', '#section-svg svg']);
});

await test('the sliders redraw the preview as polyturn geometry draws it, and it exports SVG', async () => {
  const times = [];
  for (const depth of [4, 4.5, 3, 6, 5.5, 2, 7, 3.5, 4.25, 5]) {
    await setValue('#preview-form [name=depth]', depth);
    await page.waitForFunction((d) => JSON.parse(document.querySelector('#figures').dataset.json ?? 'null')?.depth === d, depth);
    times.push(Number(await page.getAttribute('body', 'data-redraw-ms')));
  }
  assert.deepEqual(await previewJson(), geometry({ ...chosen, depth: 5 }));
  await setValue('#preview-form [name=direction]', 'opposite');
  await page.waitForFunction(() => JSON.parse(document.querySelector('#figures').dataset.json).direction === 'opposite');
  assert.deepEqual(await previewJson(), geometry({ ...chosen, depth: 5, direction: 'opposite' }));
  times.sort((a, b) => a - b);
  console.log(`     preview redraw: median ${times[5].toFixed(1)} ms, worst ${times[times.length - 1].toFixed(1)} ms (goal < 50 ms)`);
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#export-svg')]);
  const file = join(TMP, 'section.svg');
  await download.saveAs(file);
  assert.match(readFileSync(file, 'utf8'), /^<svg[^>]*xmlns="http:\/\/www.w3.org\/2000\/svg"/);
  await setValue('#preview-form [name=direction]', chosen.direction);
});

await test('a simulation runs in the worker and reports what polyturn simulate --json reports', async () => {
  await tab('simulate');
  await page.fill('#sim-form [name=revolutions]', '10');
  await page.fill('#sim-form [name=seed]', '7');
  await page.click('#sim-form button[type=submit]');
  // the page answers while the worker simulates
  const t0 = Date.now();
  const state = await page.getAttribute('body', 'data-sim');
  assert.equal(state, 'running');
  await page.evaluate(() => 1);
  assert.ok(Date.now() - t0 < 1000, 'the page stayed responsive');
  await page.waitForSelector('body[data-sim=done]', { timeout: 120000 });
  const got = await page.$eval('#sim-figures', (el) => JSON.parse(el.dataset.json));
  const want = cli('simulate', '--cutter-radius', chosen.cutter_radius, '--stock-radius', 20, '--depth', 5, '--ratio', chosen.ratio, '--edges', chosen.edges,
    '--direction', chosen.direction, '--rpm', 600, '--revolutions', 10, '--ripple', 0.02, '--start', 'rest', '--drive', 'stepper', '--seed', 7);
  for (const k of ['ticks', 'steps_emitted', 'encoder_counts', 'synced_ticks', 'final_error_steps']) assert.equal(got[k], want[k], k);
  for (const k of ['max_error_steps', 'max_error_deg', 'max_profile_deviation']) close(got[k], want[k], k);
  assert.equal(got.cut.sides, want.cut.sides);
  assert.deepEqual(got.faults, want.faults);
  assert.ok(await page.$('#sim-svg svg'), 'the section and the phase error are drawn');
  await view('simulate', ['#sim-form', '#sim-figures', '#sim-svg svg', '#sim-explain']);
});

// `polyturn <command> --help`'s [default: X] and (a..=b) for a flag: on
// the flag's line, or (clap's layout when a flag is long) the line after.
const help = (command, flag) => {
  const lines = execFileSync(POLYTURN, [command, '--help'], { encoding: 'utf8' }).split('\n');
  const i = lines.findIndex((l) => l.trim().startsWith(`${flag} `));
  const next = lines[i + 1]?.trim() ?? '';
  const line = i < 0 ? '' : lines[i] + (next.startsWith('-') ? '' : ` ${next}`);
  const range = /\((\d+)\.\.=(\d+)/.exec(line);
  return { default: /\[default: ([^\]]+)\]/.exec(line)?.[1], min: range?.[1], max: range?.[2] };
};

await test('Simulate offers the encoder and the motor with the CLI\'s defaults and ranges, and gives its result for other values', async () => {
  for (const [name, flag] of [['encoder-cpr', '--encoder-cpr'], ['motor-steps', '--motor-steps']]) {
    const cli = help('simulate', flag);
    const el = await page.$eval(`#sim-form [name=${name}]`, (e) => ({ value: e.defaultValue, min: e.min, max: e.max }));
    assert.deepEqual(el, { value: cli.default, min: cli.min, max: cli.max }, `${flag}: page ${JSON.stringify(el)}, CLI ${JSON.stringify(cli)}`);
  }
  await page.fill('#sim-form [name=revolutions]', '4');
  await page.fill('#sim-form [name=encoder-cpr]', '1000');
  await page.fill('#sim-form [name=motor-steps]', '1600');
  await page.click('#sim-form button[type=submit]');
  await page.waitForSelector('body[data-sim=done]', { timeout: 120000 });
  const got = await page.$eval('#sim-figures', (el) => JSON.parse(el.dataset.json));
  const want = cli('simulate', '--cutter-radius', chosen.cutter_radius, '--stock-radius', 20, '--depth', 5, '--ratio', chosen.ratio, '--edges', chosen.edges,
    '--direction', chosen.direction, '--rpm', 600, '--revolutions', 4, '--ripple', 0.02, '--start', 'rest', '--drive', 'stepper', '--seed', 7,
    '--encoder-cpr', 1000, '--motor-steps', 1600);
  const usual = cli('simulate', '--cutter-radius', chosen.cutter_radius, '--stock-radius', 20, '--depth', 5, '--ratio', chosen.ratio, '--edges', chosen.edges,
    '--direction', chosen.direction, '--rpm', 600, '--revolutions', 4, '--ripple', 0.02, '--start', 'rest', '--drive', 'stepper', '--seed', 7);
  assert.notEqual(want.encoder_counts, usual.encoder_counts, 'the values change the run');
  for (const k of ['ticks', 'steps_emitted', 'encoder_counts', 'synced_ticks', 'final_error_steps']) assert.equal(got[k], want[k], k);
  for (const k of ['max_error_steps', 'max_error_deg', 'max_profile_deviation']) close(got[k], want[k], k);
  assert.deepEqual(got.faults, want.faults);
  await page.fill('#sim-form [name=encoder-cpr]', '2400');
  await page.fill('#sim-form [name=motor-steps]', '3200');
});

await test('Simulate runs a BLDC cutter through the drive chosen, as polyturn simulate --drive bldc --bldc-out does', async () => {
  assert.equal(await page.isVisible('#sim-form [name=bldc-out]'), false, 'asked only for a BLDC');
  await page.selectOption('#sim-form select[name=drive]', 'bldc');
  assert.equal(await page.inputValue('#sim-form select[name=bldc-out]'), 'pwm', 'the drive that holds phase first');
  await page.fill('#sim-form [name=revolutions]', '4');
  await page.click('#sim-form button[type=submit]');
  await page.waitForSelector('body[data-sim=done]', { timeout: 120000 });
  const got = await page.$eval('#sim-figures', (el) => JSON.parse(el.dataset.json));
  const flags = ['--cutter-radius', chosen.cutter_radius, '--stock-radius', 20, '--depth', 5, '--ratio', chosen.ratio, '--edges', chosen.edges,
    '--direction', chosen.direction, '--rpm', 600, '--revolutions', 4, '--ripple', 0.02, '--start', 'rest', '--drive', 'bldc', '--seed', 7];
  const want = cli('simulate', ...flags, '--bldc-out', 'pwm');
  // an RC ESC at 50 Hz: a run that cut nothing is refused with the reason
  const esc50 = spawnSync(POLYTURN, ['simulate', ...flags.map(String), '--json'], { encoding: 'utf8' });
  if (esc50.status === 0) {
    const e = JSON.parse(esc50.stdout);
    assert.notEqual(JSON.stringify([want.faults, want.max_error_steps]), JSON.stringify([e.faults, e.max_error_steps]), 'the drive changes the run');
  } else {
    assert.match(esc50.stderr, /nothing was cut|the polygon was not cut|the controller latched/, 'the drive changes the run');
  }
  for (const k of ['ticks', 'encoder_counts', 'synced_ticks', 'final_error_steps']) assert.equal(got[k], want[k], k);
  close(got.max_error_steps, want.max_error_steps, 'max_error_steps');
  assert.deepEqual(got.faults, want.faults);
  await page.selectOption('#sim-form select[name=drive]', 'stepper');
  assert.equal(await page.isVisible('#sim-form [name=bldc-out]'), false);
});

await test('every field of Plan, Preview and Simulate shows its unit, and no view shows developer text', async () => {
  for (const scope of ['#plan-form', '#preview-form', '#sim-form']) assert.deepEqual(await unitless(scope), [], `${scope}: fields without a unit`);
  for (const name of ['plan', 'preview', 'simulate', 'flash']) await noDeveloperText(name);
  const svg = await page.textContent('#sim-svg svg');
  assert.match(svg, /drawn \d+ times larger/, 'the drawing says its magnification in words');
  assert.match(await page.textContent('#sim-explain'), /too small to see/);
});

const status = () => page.getAttribute('#status', 'data-state');
const received = () => page.evaluate(() => window.testBoard.received());
await test('the device panel connects to the real console and shows its live status', async () => {
  await tab('device');
  await page.click('#connect');
  await page.waitForFunction(() => document.querySelector('#status')?.dataset.state === 'idle', null, { timeout: 10000 });
  await page.waitForSelector('#settings input[name=ratio]');
  assert.equal(await page.inputValue('#settings input[name=cpr]'), '2400');
  await page.waitForFunction(() => document.querySelectorAll('#phase-plot polyline').length === 1);
  assert.ok((await received()).some((l) => / watch$/.test(l)), 'the panel watches');
});

await test('every board setting shows its unit, and dir, drive and enable are selects of what the console takes', async () => {
  assert.deepEqual(await unitless('#settings'), [], 'settings without a unit');
  assert.deepEqual(await unitless('#guided'), [], 'guided setup fields without a unit');
  assert.equal(await page.textContent('#settings .setting:has([name=cpr]) .unit'), 'counts/rev');
  assert.equal(await page.textContent('#settings .setting:has([name=pulse]) .unit'), 'ns');
  const options = (name) => page.$$eval(`#settings select[name=${name}] option`, (os) => os.map((o) => o.value));
  // docs/src/generated/console-settings.md: the console's own refusals
  assert.deepEqual(await options('dir'), ['same', 'opposite']);
  assert.deepEqual(await options('drive'), ['stepper', 'bldc', 'none']);
  assert.deepEqual(await options('enable'), ['high', 'low']);
  assert.equal(await page.inputValue('#settings select[name=enable]'), 'low', 'the board\'s value is selected');
  await page.selectOption('#settings select[name=dir]', 'opposite');
  await page.click('#settings button[data-name=dir]');
  await page.waitForFunction(() => document.querySelector('#settings-error').textContent === 'ok dir=opposite');
  await page.selectOption('#settings select[name=dir]', 'same');
  await page.click('#settings button[data-name=dir]');
  await page.waitForFunction(() => document.querySelector('#settings-error').textContent === 'ok dir=same');
  assert.ok((await received()).some((l) => / set dir opposite$/.test(l)));
  await noDeveloperText('device');
});

await test('a setting is set on the board; a bad one is refused in the console\'s words and never sent', async () => {
  await page.fill('#settings input[name=ratio]', '5/2');
  await page.click('#settings button[data-name=ratio]');
  await page.waitForFunction(() => document.querySelector('#settings input[name=ratio]').value === '5/2' && document.querySelector('#settings-error').textContent.startsWith('ok'));
  assert.ok((await received()).some((l) => / set ratio 5\/2$/.test(l)));
  await page.fill('#settings input[name=cpr]', '0');
  await page.waitForFunction(() => document.querySelector('#settings-error').textContent.startsWith('error'));
  const shown = await page.textContent('#settings-error');
  const console_says = await page.evaluate(async () => {
    const w = await import('/pkg/polyturn_web.js');
    const b = new w.FakeBoard();
    b.write(new TextEncoder().encode('set cpr 0\n'));
    return new TextDecoder().decode(b.read()).trim();
  });
  assert.equal(shown, console_says);
  assert.match(shown, /^error: cpr/);
  await page.click('#settings button[data-name=cpr]');
  await page.waitForTimeout(300);
  assert.ok(!(await received()).some((l) => / set cpr 0$/.test(l)), 'the refused value never reached the board');
  await page.fill('#settings input[name=cpr]', '2400');
});

await test('engage and stop change the board\'s state', async () => {
  await page.click('#engage');
  await page.waitForFunction(() => !['idle', null].includes(document.querySelector('#status').dataset.state), null, { timeout: 5000 });
  await page.click('#stop');
  await page.waitForFunction(() => document.querySelector('#status').dataset.state === 'idle', null, { timeout: 5000 });
});

const statusNow = () => page.$eval('#status', (el) => JSON.parse(el.dataset.json ?? '{}'));
await test('the simulated board\'s lathe turns at the speed set, and engage syncs the cutter to it', async () => {
  assert.ok(await page.isVisible('#sim-lathe-rpm'), 'the lathe speed is offered with the simulated board');
  await page.fill('#sim-lathe-rpm', '300');
  await page.dispatchEvent('#sim-lathe-rpm', 'change');
  await page.waitForFunction(() => Math.abs(JSON.parse(document.querySelector('#status').dataset.json).lathe_rpm - 300) < 2, null, { timeout: 10000 });
  await page.click('#engage');
  await page.waitForFunction(() => document.querySelector('#status').dataset.state === 'synced', null, { timeout: 10000 });
  const a = await statusNow();
  await page.waitForTimeout(500);
  const b = await statusNow();
  const ratio = 5 / 2; // set above
  assert.ok(Math.abs(b.cutter_rpm - 300 * ratio) < 5, `cutter ${b.cutter_rpm} rpm for the lathe's 300 x ${ratio}`);
  assert.ok(Number(b.cutter) > Number(a.cutter) && Number(b.target) > Number(a.target), `counts move: ${a.cutter} -> ${b.cutter}`);
  assert.ok(Math.abs(b.phase_err_steps) < 5, `in sync: ${b.phase_err_steps} steps`);
  await page.waitForTimeout(1500); // the phase plot fills
  await view('device', ['#status', '#settings', '#phase-plot', '#sim-lathe-rpm']);
  // the chart's scale is the synced error's, not the engage transient's
  const plot = await page.$eval('#phase-plot', (el) => ({ ...el.dataset, markers: el.querySelectorAll('.clipped').length, text: el.textContent }));
  assert.equal(plot.steadyFrom, 'synced');
  assert.ok(Number(plot.span) <= 5 && Number(plot.span) >= Math.abs(b.phase_err_steps), `the scale ±${plot.span} steps for ${b.phase_err_steps} synced`);
  assert.ok(Math.abs(Number(plot.worst)) > Number(plot.span) && plot.markers > 0, `the transient (up to ${plot.worst}) drawn past the scale with markers: ${JSON.stringify(plot)}`);
  // µm at the work: the arc of one step at the page's stock radius R2
  const r2 = await page.evaluate(async () => (await import('/js/polyturn.js')).shared.setup.stockRadius);
  const steps = Number(await page.inputValue('#settings input[name=steps]'));
  close(Number(plot.umStep), (1000 * r2 * 2 * Math.PI) / (steps * ratio), 'µm at the work per step');
  assert.ok(plot.text.includes(`µm at R2 ${r2} mm`), plot.text);
  await page.click('#stop');
  await page.fill('#sim-lathe-rpm', '0');
  await page.dispatchEvent('#sim-lathe-rpm', 'change');
  await page.waitForFunction(() => { const s = JSON.parse(document.querySelector('#status').dataset.json); return s.state === 'idle' && Number(s.lathe_rpm) === 0; }, null, { timeout: 10000 });
});

await test('the encoder check runs on the board and shows its figures', async () => {
  await page.evaluate(() => window.testBoard.set_machine(7500, 2400)); // 3.75 turns after 1.2 s at rest
  await page.click('#check-start');
  await page.waitForFunction(() => document.querySelector('#check-result').textContent.startsWith('ok encoder check started'));
  await page.click('#check-stop');
  await page.waitForFunction(() => / moved=/.test(document.querySelector('#check-result').textContent), null, { timeout: 10000 });
  assert.match(await page.textContent('#check-result'), /moved=9000 backward=0 .*cpr=2400/);
  await page.evaluate(() => window.testBoard.set_machine(0, 10));
});

await test('the dividing view: numbers refused with the range, then the hand-turned spindle read against the divisions, large, on a dial, green within a count', async () => {
  for (const bad of ['0', '1e9', 'six']) {
    await page.fill('#divide-n', bad);
    await page.evaluate(() => { document.querySelector('#divide-error').textContent = ''; });
    await page.click('#divide-start');
    await page.waitForFunction((bad) => document.querySelector('#divide-error').textContent.length > 0
      && window.testBoard.received().some((l) => l.endsWith(` divide ${bad}`)), bad);
    assert.equal(await page.textContent('#divide-error'), 'error: divide 1..=3600 divisions of a turn, at most cpr/4 (4 counts or more apart)', bad);
    assert.equal(await page.isVisible('#divide-view'), false, `${bad}: no dividing`);
  }
  await page.fill('#divide-n', '6');
  await page.click('#divide-start');
  await page.waitForSelector('#divide-view:not([hidden])', { timeout: 5000 });
  assert.equal(await page.textContent('#divide-error'), '');
  // to the next division but one: the way to the nearest, and 400 counts (0.15 degree each) more
  const s = await statusNow();
  const next = (Number(s.division) + 1) % 6;
  await page.fill('#sim-hand-deg', String(((Number(s.to_counts) + 400) * 0.15).toFixed(2)));
  await page.click('#sim-hand');
  await page.waitForFunction((next) => { const s = JSON.parse(document.querySelector('#status').dataset.json);
    return s.division === String(next) && s.within === 'yes' && s.to_counts === '0.00'; }, next, { timeout: 10000 });
  assert.equal(await page.textContent('#divide-division'), `Division ${next} of 6 at ${(next * 60).toFixed(1)}°`);
  assert.equal(await page.textContent('#divide-to'), '0.0°');
  assert.equal(await page.textContent('#divide-counts'), '0.00 counts to turn · within ±1 count');
  assert.equal(await page.textContent('#divide-angle'), `spindle ${(next * 60).toFixed(1)}° from the index`);
  const looks = () => page.evaluate(() => {
    const to = getComputedStyle(document.querySelector('#divide-to'));
    const dial = document.querySelector('#divide-dial').getBoundingClientRect();
    const mark = document.querySelector('#divide-dial line.division');
    return { px: parseFloat(to.fontSize), colour: to.color, dial: [dial.width, dial.height], ticks: document.querySelectorAll('#divide-dial line').length,
      mark: [mark.getAttribute('x2'), mark.getAttribute('y2')], within: document.querySelector('#divide-view').dataset.within };
  });
  const on = await looks();
  // large: 120 px digits (3 cm on a 96 dpi screen), a dial 320 px across
  assert.ok(on.px >= 96 && on.dial[0] >= 300 && on.dial[1] >= 300, JSON.stringify(on));
  assert.equal(on.colour, 'rgb(0, 119, 0)', 'green within a count');
  assert.equal(on.ticks, 7, 'six divisions and the spindle');
  const rim = (deg) => [160 + 156 * Math.sin(deg * Math.PI / 180), 160 - 156 * Math.cos(deg * Math.PI / 180)].map((v) => v.toFixed(1));
  assert.deepEqual(on.mark, rim(next * 60), 'the division marked where it is on the dial');
  await view('device', ['#divide-dial', '#divide-to', '#divide-division'], { shot: 'device-dividing', at: '#dividing' });
  // 20 degrees back: not there, the way to it forward, not green
  await page.fill('#sim-hand-deg', '-20');
  await page.click('#sim-hand');
  await page.waitForFunction(() => document.querySelector('#divide-view').dataset.within === 'no' && document.querySelector('#divide-to').textContent === '+20.0°', null, { timeout: 10000 });
  assert.equal(await page.textContent('#divide-counts'), '+133.00 counts to turn · not there');
  assert.notEqual((await looks()).colour, 'rgb(0, 119, 0)');
  // the cutter stays off: engage is refused with the reason, nothing changes
  await page.click('#engage');
  await page.waitForFunction(() => /error: dividing \(the chuck is turned by hand, the cutter stays off\): divide stop first/.test(document.querySelector('#log').textContent));
  assert.equal((await statusNow()).state, 'idle');
  await page.click('#divide-stop');
  await page.waitForSelector('#divide-view', { state: 'hidden', timeout: 5000 });
  assert.ok((await received()).some((l) => / divide stop$/.test(l)));
});

await test('the guided setup sends the settings polyturn device setup derives', async () => {
  await page.fill('#guided [name=lines]', '500');
  await page.fill('#guided [name=microsteps]', '8');
  await page.click('#guided button[type=submit]');
  await page.waitForFunction(() => document.querySelector('#guided-result').textContent.includes('not saved yet'), null, { timeout: 10000 });
  assert.match(await page.textContent('#guided-result'), /set: .*cpr=2000/);
  await page.waitForFunction(() => document.querySelector('#settings input[name=cpr]')?.value === '2000');
  assert.equal(await page.inputValue('#settings input[name=steps]'), '1600');
});

await test('the guided setup sets a BLDC cutter from its drive, its encoder and its full speed', async () => {
  assert.equal(await page.isVisible('#guided [name=cutter-cpr]'), false, 'a stepper\'s form first');
  await page.selectOption('#guided select[name=cutter]', 'pwm');
  assert.equal(await page.isVisible('#guided [name=microsteps]'), false, 'no microsteps for a BLDC');
  await page.fill('#guided [name=cutter-cpr]', '4000');
  await page.fill('#guided [name=cutter-max-rpm]', '3000');
  await page.fill('#guided [name=pwm-hz]', '7000');
  await page.click('#guided button[type=submit]');
  await page.waitForFunction(() => document.querySelector('#guided-result').textContent.startsWith('error'), null, { timeout: 10000 });
  assert.match(await page.textContent('#guided-result'), /pwm-hz/, 'a PWM the timer cannot make: refused, naming it');
  await page.fill('#guided [name=pwm-hz]', '2000');
  await page.click('#guided button[type=submit]');
  await page.waitForFunction(() => document.querySelector('#guided-result').textContent.includes('not saved yet'), null, { timeout: 10000 });
  const result = await page.textContent('#guided-result');
  assert.match(result, /set: .*drive=bldc/);
  assert.match(result, /bldc-out pwm at 2000 Hz/);
  await page.waitForFunction(() => document.querySelector('#settings [name=drive]')?.value === 'bldc');
  assert.equal(await page.inputValue('#settings input[name=steps]'), '4000');
  assert.equal(await page.inputValue('#settings input[name=max-rate]'), '200000');
  // back to the stepper the other checks expect
  await page.selectOption('#guided select[name=cutter]', 'stepper');
  await page.click('#guided button[type=submit]');
  await page.waitForFunction(() => document.querySelector('#settings [name=drive]')?.value === 'stepper');
});

await test('a compensating table goes only to a board set for its ratio and edges', async () => {
  const table = join(TMP, 'flats.json');
  execFileSync(POLYTURN, ['compensate', '--cutter-radius', '50', '--stock-radius', '10', '--depth', '2', '--ratio', '3', '--edges', '2', '--direction', 'same', '--rpm', '20', '--x-max-speed', '12.5', '--x-max-accel', '5000', '--encoder-cpr', '2000', '--table', table]);
  const begun = (await received()).filter((l) => / cam begin /.test(l)).length;
  await page.evaluate(() => { document.querySelector('#cam-result').textContent = ''; });
  await page.setInputFiles('#cam-file', table);
  await page.click('#cam-upload');
  await page.waitForFunction(() => /^(uploaded|error)/.test(document.querySelector('#cam-result').textContent), null, { timeout: 30000 });
  const result = await page.textContent('#cam-result');
  assert.match(result, /^error: upload-cam: the table was made for ratio 3 with 2 edges, the board is set to ratio \S+ with \d+ edges: /, result);
  assert.equal((await received()).filter((l) => / cam begin /.test(l)).length, begun, 'nothing was sent');
});

await test('a cam table from polyturn cam uploads through the console', async () => {
  const table = join(TMP, 'cam.json');
  execFileSync(POLYTURN, ['cam', '--sides', '4', '--inscribed-radius', '10', '--rpm', '60', '--x-max-speed', '12', '--x-max-accel', '5000', '--encoder-counts', '2000', '--table', table]);
  // a single-point tool's table goes only to a board with no cutter
  await page.evaluate(() => { document.querySelector('#cam-result').textContent = ''; });
  await page.setInputFiles('#cam-file', table);
  await page.click('#cam-upload');
  await page.waitForFunction(() => /^(uploaded|error)/.test(document.querySelector('#cam-result').textContent), null, { timeout: 30000 });
  assert.match(await page.textContent('#cam-result'), /^error: upload-cam: the table is a single-point tool's \(polyturn cam\), the board is set to drive=stepper: set drive none first/);
  await page.selectOption('#settings select[name=drive]', 'none');
  await page.click('#settings button[data-name=drive]');
  await page.waitForFunction(() => document.querySelector('#settings [name=drive]')?.value === 'none');
  await page.evaluate(() => { document.querySelector('#cam-result').textContent = ''; });
  await page.setInputFiles('#cam-file', table);
  await page.click('#cam-upload');
  await page.waitForFunction(() => /^(uploaded|error)/.test(document.querySelector('#cam-result').textContent), null, { timeout: 30000 });
  const result = await page.textContent('#cam-result');
  assert.match(result, /^uploaded \d+ lines: ok/, `${result}\n${(await received()).slice(-6).join('\n')}\n${(await page.textContent('#log')).split('\n').slice(-8).join('\n')}`);
  assert.ok((await received()).some((l) => / cam begin /.test(l)));
});

await test('the DfuSe layer writes, verifies and leaves a fake ROM bootloader', async () => {
  const r = await page.evaluate(async () => {
    const w = await import('/pkg/polyturn_web.js');
    const { flash } = await import('/js/dfu.js');
    const rom = new w.FakeDfu(0, 0);
    rom.preload(0x08000000, new Uint8Array(64).fill(0x55)); // an older image
    const { functionalDescriptor } = await import('/js/flash.js');
    const plan = w.flash_plan('polyturn.bin', w.FakeDfu.sample_image(40000), rom.interface(), functionalDescriptor(rom.configuration_descriptor()));
    const t = { controlIn: async (q, v, n) => rom.control_in(q, v, n), controlOut: async (q, v, d) => rom.control_out(q, v, d) };
    const phases = [];
    const out = await flash(t, plan, (p) => { if (phases.at(-1) !== p.phase) phases.push(p.phase); });
    const back = rom.read(0x08000000, plan.bytes.length);
    return { out, phases, same: back.every((b, i) => b === plan.bytes[i]), len: plan.bytes.length, events: rom.events() };
  });
  assert.deepEqual(r.out, { left: 'manifest' });
  assert.deepEqual(r.phases, ['erase', 'write', 'verify', 'leave']);
  assert.ok(r.same, 'flash holds the image');
  assert.equal(r.len, 40960, 'padded to whole 2 KiB transfers');
  assert.deepEqual(r.events.filter((e) => e.startsWith('Erase')), ['Erase(134217728)', 'Erase(134234112)', 'Erase(134250496)'], 'sectors 0-2 only');
  assert.equal(r.events.at(-1), 'Leave');
});

await test('a byte that reads back wrong fails the flash naming its address', async () => {
  const e = await page.evaluate(async () => {
    const w = await import('/pkg/polyturn_web.js');
    const { flash } = await import('/js/dfu.js');
    const rom = new w.FakeDfu(0x08000100, 0x01);
    const { functionalDescriptor } = await import('/js/flash.js');
    const plan = w.flash_plan('polyturn.bin', w.FakeDfu.sample_image(4096), rom.interface(), functionalDescriptor(rom.configuration_descriptor()));
    const t = { controlIn: async (q, v, n) => rom.control_in(q, v, n), controlOut: async (q, v, d) => rom.control_out(q, v, d) };
    try { await flash(t, plan); return 'no error'; } catch (err) { return { msg: err.message, events: rom.events() }; }
  });
  assert.match(e.msg, /^verify failed at 0x08000100: wrote 0x[0-9a-f]{2}, read back 0x[0-9a-f]{2}$/);
  assert.ok(!e.events.includes('Leave'), 'the board stays in its bootloader');
});

await test('the page reads the ROM\'s functional descriptor and refuses what polyturn flash refuses', async () => {
  const r = await page.evaluate(async () => {
    const w = await import('/pkg/polyturn_web.js');
    const { functionalDescriptor } = await import('/js/flash.js');
    const rom = new w.FakeDfu(0, 0);
    const f = functionalDescriptor(rom.configuration_descriptor());
    const image = w.FakeDfu.sample_image(4096);
    const plan = (d) => { try { return w.flash_plan('polyturn.bin', image, rom.interface(), d).transfer; } catch (e) { return String(e); } };
    const dfu11 = Uint8Array.from(f); dfu11[7] = 0x10; // bcdDFUVersion 1.10: plain DFU
    const small = Uint8Array.from(f); small[5] = 32; small[6] = 0; // wTransferSize 32
    const bare = functionalDescriptor(new Uint8Array([9, 2, 9, 0, 1, 1, 0, 0xc0, 0x32])); // no 0x21 in it
    return { f: Array.from(f), ok: plan(f), dfu11: plan(dfu11), small: plan(small), bare, none: plan(new Uint8Array()) };
  });
  // lsusb -v of 0483:df11: attributes 0x0b, detach 255 ms, transfer 2048, DFU 1.1a
  assert.deepEqual(r.f, [9, 0x21, 0x0b, 0xff, 0, 0, 8, 0x1a, 1]);
  assert.equal(r.ok, 2048);
  assert.match(r.dfu11, /^not the STM32 ROM bootloader's DfuSe 1\.1a/);
  assert.match(r.small, /transfer size 32/);
  assert.equal(r.bare, null);
  assert.match(r.none, /^the device's DFU functional descriptor is not one/);
});

await test('a bootloader that goes astray fails the flash: a wrong state, no answer, a refused leave', async () => {
  const r = await page.evaluate(async () => {
    const w = await import('/pkg/polyturn_web.js');
    const { flash, Stall } = await import('/js/dfu.js');
    const { functionalDescriptor } = await import('/js/flash.js');
    // `bend(rom, q, v, d)` may answer in the ROM's place (undefined: the ROM answers)
    const run = async (bend) => {
      const rom = new w.FakeDfu(0, 0);
      const plan = w.flash_plan('polyturn.bin', w.FakeDfu.sample_image(4096), rom.interface(), functionalDescriptor(rom.configuration_descriptor()));
      const t = {
        controlIn: async (q, v, n) => (await bend('in', rom, q, v, n)) ?? rom.control_in(q, v, n),
        controlOut: async (q, v, d) => (await bend('out', rom, q, v, d)) ?? rom.control_out(q, v, d),
      };
      const t0 = performance.now();
      try {
        const out = await flash(t, plan, () => {}, { stepMs: 300 });
        return { out, events: rom.events() };
      } catch (e) {
        return { error: e.message, ms: performance.now() - t0, events: rom.events() };
      }
    };
    let erased = false;
    return {
      // a status of dfuIDLE (state 2) after the first erase, not dfuDNLOAD-IDLE
      idle: await run(async (dir, rom, q, v, n) => {
        if (dir === 'out' && q === 1 && n[0] === 0x41) erased = true;
        if (dir === 'in' && q === 3 && erased) { const s = rom.control_in(q, v, n); s[4] = 2; return s; }
      }),
      // the first data block is never answered
      silent: await run(async (dir, rom, q, v, d) => (dir === 'out' && q === 1 && v === 2 && d.length > 0 ? new Promise(() => {}) : undefined)),
      // the board drops off the bus at the leave request: it left
      vanished: await run(async (dir, rom, q, v, d) => { if (dir === 'out' && q === 1 && v === 2 && d.length === 0) throw new Error('NetworkError: device disconnected'); }),
      // the board stalls the leave request: it refused
      stalled: await run(async (dir, rom, q, v, d) => { if (dir === 'out' && q === 1 && v === 2 && d.length === 0) throw new Stall('stall (stall)'); }),
    };
  });
  assert.match(r.idle.error ?? '', /^the erase of sector 0 at 0x08000000: the bootloader went to state 2 \(OK\), not dfuDNLOAD-IDLE$/, JSON.stringify(r.idle));
  assert.match(r.silent.error ?? '', /^USB transfer failed during the write at 0x08000000: no answer to the request within 0\.3 s/, JSON.stringify(r.silent));
  assert.ok(r.silent.ms < 2000, `bounded: ${r.silent.ms} ms`);
  assert.ok(!r.silent.events.includes('Leave'));
  assert.deepEqual(r.vanished.out, { left: 'vanished' });
  assert.match(r.stalled.error ?? '', /^USB transfer failed during the leave request: stall/, JSON.stringify(r.stalled));
});

await test('a file that is no polyturn image is refused before any request', async () => {
  const e = await page.evaluate(async () => {
    const w = await import('/pkg/polyturn_web.js');
    try { w.flash_plan('notes.bin', new TextEncoder().encode('hello'), new w.FakeDfu(0, 0).interface(), new Uint8Array()); return 'taken'; } catch (err) { return String(err); }
  });
  assert.match(e, /^notes\.bin /);
});

await test('an image cut short, grown or with a byte changed is refused before any request, as polyturn flash refuses it', async () => {
  const r = await page.evaluate(async () => {
    const w = await import('/pkg/polyturn_web.js');
    const { functionalDescriptor } = await import('/js/flash.js');
    const rom = new w.FakeDfu(0, 0);
    const desc = functionalDescriptor(rom.configuration_descriptor());
    const image = w.FakeDfu.sample_image(40000);
    const plan = (bytes) => { try { w.flash_plan('polyturn.bin', bytes, rom.interface(), desc); return null; } catch (e) { return String(e); } };
    // a fixed sequence of random mutants (xorshift32), as the host's property test makes them
    let x = 46;
    const rand = (n) => { x ^= x << 13; x >>>= 0; x ^= x >>> 17; x ^= x << 5; x >>>= 0; return x % n; };
    const taken = [];
    const seal = [];
    for (let i = 0; i < 200; i++) {
      let m;
      let what;
      switch (i % 4) {
        case 0: { const keep = 1 + rand(image.length - 1); m = image.slice(0, keep); what = `cut to ${keep}`; break; }
        case 1: { const more = 1 + rand(63); m = new Uint8Array(image.length + more); m.set(image); for (let j = image.length; j < m.length; j++) m[j] = rand(256); what = `${more} bytes appended`; break; }
        case 2: { const at = rand(0x198); m = image.slice(); m[at] ^= 1 + rand(255); what = `vector-table byte ${at} changed`; break; }
        default: { const at = rand(image.length); m = image.slice(); m[at] ^= 1 + rand(255); what = `byte ${at} changed`; }
      }
      const e = plan(m);
      if (e === null) taken.push(what);
      else if (/must end with the seal/.test(e)) seal.push(what);
    }
    return { whole: plan(image), taken, seal: seal.length, events: rom.events() };
  });
  assert.equal(r.whole, null, 'the whole image is taken');
  assert.deepEqual(r.taken, [], 'every mutant refused');
  assert.ok(r.seal >= 100, `${r.seal} of 200 refused by the seal (the others by the vector table or the marker)`);
  assert.deepEqual(r.events, [], 'no request reached the bootloader');
});

await test('a port that echoes the command is never taken for the board, and the board behind it is heard', async () => {
  const got = await page.evaluate(async () => {
    const { Session } = await import('/js/serial.js');
    const lib = await (await import('/js/polyturn.js')).load();
    const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
    // a loopback plug (no board), or an adapter echoing in front of the real console
    const echoing = (board) => {
      const queue = [];
      return {
        readable: new ReadableStream({
          async pull(c) {
            for (;;) {
              if (queue.length) return c.enqueue(queue.shift());
              const r = board ? board.read() : [];
              if (r.length) return c.enqueue(r);
              await sleep(5);
            }
          },
        }),
        writable: new WritableStream({ write(chunk) { queue.push(chunk); if (board) board.write(chunk); } }),
        async open() {},
        async close() {},
      };
    };
    const outcome = (p) => p.then((r) => `ok|${r}`, (e) => `err|${e.message}`);
    const alone = await Session.open(echoing(null));
    const behind = await Session.open(echoing(new lib.FakeBoard()));
    return {
      alone: await outcome(alone.ask('set cpr 1000', 300)),
      refused: await outcome(behind.ask('set cpr 0', 1000)),
      read: await outcome(behind.ask('get cpr', 1000)),
      asReply: await outcome(behind.ask('ok fine', 1000)),
    };
  });
  assert.match(got.alone, /^err\|no reply to 'set' within 300 ms: the port echoed the command back/);
  assert.match(got.refused, /^err\|error: /, 'the board\'s refusal behind the echo is a refusal');
  assert.match(got.read, /^ok\|ok .*2400/);
  assert.match(got.asReply, /^err\|the command 'ok fine' reads as a reply/);
});

await test('the flash view offers the image polyturn web carries, and nothing when it carries none', async () => {
  // a release polyturn (POLYTURN=target/dist/.../polyturn) carries one; a plain build none
  const named = (await fetch(url, { method: 'HEAD' })).headers.get('x-polyturn-firmware');
  const line = () => page.evaluate(() => { const e = document.getElementById('image-carried'); return e.hidden ? null : e.textContent; });
  if (!named) return assert.equal(await line(), null);
  await page.waitForFunction(() => !document.getElementById('image-carried').hidden, null, { timeout: 5000 });
  assert.equal(await line(), `No file chosen: writes ${named.split('/').pop()}, the image this polyturn carries.`);
  assert.equal((await fetch(url + named)).status, 200);
});

const VERSION = execFileSync(POLYTURN, ['--version'], { encoding: 'utf8' }).trim().split(' ')[1];
await test('the Flash view names the release image, says to switch the motor power off, and offers a carried image', async () => {
  await tab('flash');
  const text = await page.textContent('#flash');
  assert.ok(text.includes(`polyturn-${VERSION}-stm32f411ce.bin`), `the file .ci/release-image writes: ${text}`);
  assert.ok(!text.includes('polyturn-firmware.bin'), 'no build makes polyturn-firmware.bin');
  assert.match(await page.textContent('#power-off'), /motor's power off/);
  await view('flash', ['#flash ol', '#flash-go', '#image-file']);
  // as the polyturn web of a release serves it (X-Polyturn-Firmware), here
  // on a second page whatever polyturn serves this run
  const named = `firmware/polyturn-${VERSION}-stm32f411ce.bin`;
  const other = await browser.newPage({ viewport: { width: 1280, height: 900 } });
  await other.route('**/index.html', async (route) => {
    const r = await route.fetch();
    await route.fulfill({ response: r, headers: { ...r.headers(), 'x-polyturn-firmware': named } });
  });
  await other.goto(url);
  await other.waitForSelector('body[data-ready=yes]', { timeout: 30000 });
  await other.click('nav button[data-tab=flash]');
  await other.waitForSelector('#image-carried:not([hidden])', { timeout: 5000 });
  assert.equal(await other.textContent('#image-carried'), `No file chosen: writes polyturn-${VERSION}-stm32f411ce.bin, the image this polyturn carries.`);
  assert.equal(await other.getAttribute('#image-carried a', 'href'), named);
  await other.close();
});

await test('the page logged no errors', async () => {
  assert.deepEqual(errors, []);
});

await browser.close();
server.kill();
const failed = results.filter(([, r]) => r !== 'ok');
console.log(`${results.length - failed.length} passed, ${failed.length} failed`);
process.exit(failed.length ? 1 : 0);
