// The page's Device view against the real firmware image, through
// `polyturn web --board`, in headless Chromium with WebSerial switched
// off: the emulator (`polyturn-emu ELF --pty`, docs/src/emulator.md) is
// the board, its console's pseudo-terminal the port polyturn web relays.
//   1. with --listen 127.0.0.1 (the token asked): no token, a 401 and no
//      page; with it, status, `set ratio 11/3`, a value refused before
//      sending, a second page that only watches, save, NRST (SIGUSR1) and
//      `get` after it, control passing to the second page when the first
//      closes, and the board going away (the emulator killed): the page
//      says so and offers to reconnect, and reconnecting says why not
//   2. a lathe turning at 300 rpm (--lathe-rpm): engage until synced,
//      the phase chart scaled to the synced error with the transient
//      marked, and `save` refused by the board while the lathe turns
// `node relay.mjs` after `bash web/build`, `cargo build -p polyturn-host`,
// `cargo fw` and `cargo build --release -p polyturn-emu` (.ci/run's order).
// Prints each scenario's wall time; exits non-zero naming the failed check.
import { chromium } from 'playwright-core';
import { spawn } from 'node:child_process';
import { existsSync } from 'node:fs';
import { join } from 'node:path';
import assert from 'node:assert/strict';

const ROOT = new URL('../..', import.meta.url).pathname;
const T = process.env.CARGO_TARGET_DIR ?? join(ROOT, 'target');
const POLYTURN = process.env.POLYTURN ?? join(T, 'debug/polyturn');
const EMU = process.env.EMU ?? join(T, 'release/polyturn-emu');
const ELF = process.env.ELF ?? join(T, 'thumbv7em-none-eabihf/fw/polyturn-firmware');
const SHOTS = process.env.SCREENSHOTS;
for (const [what, f] of [['polyturn', POLYTURN], ['polyturn-emu', EMU], ['the firmware ELF', ELF]]) {
  if (!existsSync(f)) { console.log(`relay: no ${what} at ${f}: build it first (see the head of this file)`); process.exit(2); }
}

const children = [];
// A child process and the first line of its stdout matching `want`.
function start(cmd, args, want, what) {
  const child = spawn(cmd, args);
  children.push(child);
  child.err = '';
  child.stderr.on('data', (d) => { child.err += d; });
  const line = new Promise((resolve, reject) => {
    let out = '';
    child.stdout.on('data', (d) => { out += d; const m = want.exec(out); if (m) resolve(m[0]); });
    child.on('exit', (c) => reject(new Error(`${what} exited ${c}: ${child.err}`)));
    // a shared machine under load boots the emulated board in seconds
    setTimeout(() => reject(new Error(`${what} printed nothing within 60 s: ${child.err}`)), 60000);
  });
  return { child, line };
}
const stop = (child) => new Promise((resolve) => {
  if (child.exitCode !== null || child.signalCode !== null) return resolve();
  child.on('exit', resolve);
  child.kill();
});

async function board(flags = []) {
  const emu = start(EMU, [ELF, '--pty', ...flags], /\/dev\/pts\/\d+(?=\s)/, 'polyturn-emu');
  return { emu: emu.child, pty: await emu.line };
}
async function relay(pty, flags = []) {
  const web = start(POLYTURN, ['web', '--no-open', '--port', '0', '--dir', join(ROOT, 'web/www'), '--board', pty, ...flags], /http:\/\/\S+(?= )/, 'polyturn web');
  return { web: web.child, url: await web.line };
}

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
  args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking', '--disable-component-update', '--disable-sync'],
});
// a browser without WebSerial, as Firefox or Safari
async function newContext() {
  const context = await browser.newContext({ viewport: { width: 1280, height: 900 } });
  await context.addInitScript(() => { delete Navigator.prototype.serial; });
  return context;
}
const errors = [];
const pages = [];
async function open(context, url) {
  const page = await context.newPage();
  pages.push(page);
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto(url, { timeout: 60000 });
  await page.waitForSelector('body[data-ready=yes]', { timeout: 30000 });
  await page.click('nav button[data-tab=device]');
  return page;
}
const state = (page) => page.$eval('#status', (el) => JSON.parse(el.dataset.json ?? '{}'));
const waitFor = (page, f, arg, ms = 20000) => page.waitForFunction(f, arg, { timeout: ms });
const logHas = (page, text, ms) => waitFor(page, (t) => document.querySelector('#log').textContent.includes(t), text, ms);
async function connect(page) {
  await page.click('#connect-relay');
  await waitFor(page, () => !document.querySelector('#relay-state').hidden);
}
async function setOne(page, name, value) {
  await page.fill(`#settings input[name=${name}]`, value);
  await page.click(`#settings button[data-name=${name}]`);
  await waitFor(page, (want) => document.querySelector('#settings-error').textContent === want, `ok ${name}=${value}`);
  // and the form is read back (`get`) before the next step
  await waitFor(page, ([sent, kv]) => {
    const after = document.querySelector('#log').textContent.split(sent).at(-1);
    return after.split('> get\n')[1]?.split('\n')[0].includes(kv);
  }, [`> set ${name} ${value}\n`, ` ${name}=${value}`]);
}

const results = [];
async function scenario(name, f) {
  const t0 = Date.now();
  try {
    await f();
    results.push([name, 'ok']);
    console.log(`ok   ${name} (${((Date.now() - t0) / 1000).toFixed(1)} s wall)`);
  } catch (e) {
    results.push([name, 'FAILED']);
    console.log(`FAIL ${name}\n     ${String(e.stack ?? e).split('\n').slice(0, 16).join('\n     ')}`);
    for (const p of pages.filter((p) => !p.isClosed())) {
      const seen = await p.evaluate(() => [document.querySelector('#settings-error')?.textContent, document.querySelector('#relay-state')?.textContent, document.querySelector('#log')?.textContent.split('\n').slice(-12).join(' | ')]).catch(() => []);
      console.log(`     a page: ${seen.join(' || ')}`);
    }
  }
}

let emu; let web; let url; let pty;
await scenario('boot: the emulated board on a pty, relayed by polyturn web --listen 127.0.0.1 with a token', async () => {
  ({ emu, pty } = await board());
  ({ web, url } = await relay(pty, ['--listen', '127.0.0.1']));
  assert.match(url, /^http:\/\/127\.0\.0\.1:\d+\/\?token=[0-9a-f]{32}$/);
});

const bare = () => url.replace(/\?token=.*/, '');
await scenario('without the token: 401 for the page and the relay, and nothing of the console', async () => {
  for (const path of ['', 'relay', 'js/main.js', '?token=00000000000000000000000000000000']) {
    const r = await fetch(`${bare()}${path}`);
    const body = await r.text();
    assert.equal(r.status, 401, `/${path}`);
    assert.ok(!/state=|<html/.test(body), `/${path} gave: ${body}`);
  }
  const context = await newContext();
  const page = await context.newPage();
  const r = await page.goto(bare());
  assert.equal(r.status(), 401);
  await context.close();
});

let context; let first; let second;
await scenario('through the relay with WebSerial off: status, set ratio 11/3, a refused value never sent', async () => {
  context = await newContext();
  first = await open(context, url);
  assert.equal(await first.evaluate(() => 'serial' in navigator), false, 'WebSerial is off');
  assert.ok(await first.isDisabled('#connect'));
  assert.match(await first.textContent('#serial-support'), /served with the board/);
  await connect(first);
  assert.equal(await first.textContent('#relay-state'), 'This page has control of the board.');
  await waitFor(first, () => document.querySelector('#status').dataset.state === 'idle');
  const s = await state(first);
  assert.equal(s.fault, 'none');
  assert.match(await first.textContent('#connect-relay'), new RegExp(`Connected through polyturn web \\(${pty}\\)`));
  // 11/3 at the default max-rpm 1500 would overspeed the motor: refused
  await setOne(first, 'max-rpm', '1000');
  await setOne(first, 'ratio', '11/3');
  await first.fill('#settings input[name=cpr]', '0');
  await waitFor(first, () => document.querySelector('#settings-error').textContent.startsWith('error: cpr'));
  await first.click('#settings button[data-name=cpr]');
  await first.waitForTimeout(300);
  assert.ok(!(await first.textContent('#log')).includes('> set cpr 0'), 'the refused value was sent');
  await first.fill('#settings input[name=cpr]', '2400');
});

await scenario('a second page watches: refused control, its buttons off, the status streaming', async () => {
  second = await open(context, bare()); // the cookie the token set carries it
  await connect(second);
  assert.equal(await second.textContent('#relay-state'), 'Another page has control of the board; this one watches its status.');
  assert.ok(await second.isDisabled('#engage') && await second.isDisabled('#save') && await second.isDisabled('#take-control'));
  await waitFor(second, () => document.querySelector('#status').dataset.state === 'idle');
});

await scenario('save, NRST by hand, then get: the board kept ratio 11/3', async () => {
  await first.click('#save');
  await logHas(first, 'ok saved');
  const before = (emu.err.match(/^emu: reset at/gm) ?? []).length;
  emu.kill('SIGUSR1');
  await new Promise((resolve, reject) => {
    const t0 = Date.now();
    const look = setInterval(() => {
      if ((emu.err.match(/^emu: reset at/gm) ?? []).length > before) { clearInterval(look); resolve(); }
      if (Date.now() - t0 > 20000) { clearInterval(look); reject(new Error(`no reset line: ${emu.err}`)); }
    }, 100);
  });
  await first.fill('#settings input[name=ratio]', '2');
  await first.click('#read-settings');
  await waitFor(first, () => document.querySelector('#settings input[name=ratio]').value === '11/3');
  assert.match((await first.textContent('#log')).split('> get\n').at(-1), /^ok .*ratio=11\/3/, 'get after the reset');
});

await scenario('the controlling page closes: the watcher takes control', async () => {
  await first.close();
  await waitFor(second, () => document.querySelector('#relay-state').textContent.startsWith('Nobody has control'));
  await second.click('#take-control');
  await waitFor(second, () => document.querySelector('#relay-state').textContent === 'This page has control of the board.');
  await waitFor(second, () => document.querySelector('#settings input[name=ratio]')?.value === '11/3');
  assert.ok(await second.isEnabled('#engage'));
});

await scenario('the board goes away: the page says so, offers to reconnect, and nothing is sent again', async () => {
  await stop(emu);
  await waitFor(second, () => document.querySelector('#relay-state').textContent.includes('went away'));
  assert.match(await second.textContent('#relay-state'), new RegExp(`^The board on ${pty} went away .*Nothing that was waiting for a reply was sent again\\. Reconnect when it is back\\.$`));
  assert.equal(await second.textContent('#connect-relay'), 'Reconnect');
  assert.ok(await second.isDisabled('#engage'));
  await second.click('#connect-relay');
  await logHas(second, `connect: cannot open ${pty}`);
  assert.ok(await second.isEnabled('#connect-relay'), 'reconnect is offered again');
  await context.close();
  await stop(web);
});

await scenario('a turning lathe: engage until synced, the chart on the synced error, save refused by the board', async () => {
  ({ emu, pty } = await board(['--lathe-rpm', '300']));
  ({ web, url } = await relay(pty));
  assert.match(url, /^http:\/\/127\.0\.0\.1:\d+\/$/, 'on loopback no token is asked');
  context = await newContext();
  const page = await open(context, url);
  await connect(page);
  await waitFor(page, () => Math.abs(Number(JSON.parse(document.querySelector('#status').dataset.json ?? '{}').lathe_rpm) - 300) < 5, null, 30000);
  await setOne(page, 'max-rpm', '1000');
  await setOne(page, 'ratio', '11/3');
  await page.click('#engage');
  await waitFor(page, () => document.querySelector('#status').dataset.state === 'synced', null, 60000);
  await page.waitForTimeout(3000); // the chart has synced samples
  const plot = await page.$eval('#phase-plot', (el) => ({ ...el.dataset, markers: el.querySelectorAll('.clipped').length, text: el.textContent }));
  const s = await state(page);
  assert.equal(plot.steadyFrom, 'synced');
  assert.ok(Number(plot.span) <= 5 && Math.abs(s.phase_err_steps) <= Number(plot.span), `scale ±${plot.span} steps for ${s.phase_err_steps} synced`);
  assert.ok(Math.abs(Number(plot.worst)) > Number(plot.span) && plot.markers > 0, `the transient (up to ${plot.worst}) marked past the scale: ${JSON.stringify(plot)}`);
  assert.match(plot.text, /µm at R2/);
  if (SHOTS) await page.screenshot({ path: join(SHOTS, 'web-device-relay.png') });
  await page.click('#stop');
  await waitFor(page, () => document.querySelector('#status').dataset.state === 'idle', null, 30000);
  await page.click('#save');
  await waitFor(page, () => /> save\n.+\n/.test(document.querySelector('#log').textContent));
  const reply = (await page.textContent('#log')).split('> save\n')[1].split('\n')[0];
  assert.match(reply, /^error: stop the lathe first: /, 'the board refuses save while the lathe turns');
  await context.close();
});

assert.deepEqual(errors, [], 'the pages logged errors');
await browser.close();
await Promise.all(children.map(stop));
const failed = results.filter(([, r]) => r !== 'ok');
console.log(`${results.length - failed.length} passed, ${failed.length} failed`);
process.exit(failed.length ? 1 : 0);
