// Flash: a release image to a board in ROM DFU mode over WebUSB
// (Chromium), checked and planned by the host library first.
import { load } from './polyturn.js';
import { bounded, flash, webusb } from './dfu.js';

const $ = (id) => document.getElementById(id);
// AN2606: the STM32 ROM bootloader's USB DFU
const ROM = { vendorId: 0x0483, productId: 0xdf11 };

export async function init() {
  // the file .ci/release-image writes and the release bundle ships
  $('release-image').textContent = (await load()).release_image();
  const supported = 'usb' in navigator;
  $('usb-support').textContent = supported
    ? 'Chromium, Chrome or Edge: WebUSB finds the board in DFU mode (on Linux a udev rule may be needed, see the manual).'
    : 'This browser has no WebUSB: use Chromium, Chrome or Edge, or `polyturn flash`.';
  $('flash-go').disabled = !supported;
  $('flash-go').addEventListener('click', go);
  offerCarried().catch(() => {}); // nothing offered is the old page
}

// A release `polyturn web` serves the firmware it carries and names it in
// the X-Polyturn-Firmware header of every file; offered when no file is
// chosen. Another host sends no such header, and nothing is offered.
let carried = null;
async function offerCarried() {
  const r = await fetch('index.html', { method: 'HEAD' });
  const url = r.headers.get('X-Polyturn-Firmware');
  if (!r.ok || !url) return;
  carried = { name: url.split('/').pop(), url };
  const line = $('image-carried');
  line.replaceChildren('No file chosen: writes ', Object.assign(document.createElement('a'), { href: url, textContent: carried.name }),
    ', the image this polyturn carries.');
  line.hidden = false;
}

// The chosen file, else the carried image: {name, bytes}, or null.
async function image() {
  const file = $('image-file').files[0];
  if (file) return { name: file.name, bytes: new Uint8Array(await file.arrayBuffer()) };
  if (!carried) return null;
  const r = await fetch(carried.url);
  if (!r.ok) throw new Error(`${carried.name}: the server answered ${r.status}`);
  return { name: carried.name, bytes: new Uint8Array(await r.arrayBuffer()) };
}

// The alternate setting whose name is the internal flash's layout.
export function findFlash(device) {
  for (const iface of device.configuration?.interfaces ?? []) {
    for (const alt of iface.alternates) {
      if (alt.interfaceClass === 0xfe && alt.interfaceSubclass === 1 && (alt.interfaceName ?? '').startsWith('@Internal Flash')) {
        return { interfaceNumber: iface.interfaceNumber, alternate: alt.alternateSetting, name: alt.interfaceName };
      }
    }
  }
  return null;
}

// The DFU functional descriptor (type 0x21, DFU 1.1 §4.1.3) among the
// descriptors a configuration descriptor carries (USB 2.0 §9.4.3: each
// starts with its length and type). Null if there is none.
export function functionalDescriptor(config) {
  for (let i = 0; i + 1 < config.length && config[i] > 0; i += config[i]) {
    if (config[i + 1] === 0x21) return config.subarray(i, i + config[i]);
  }
  return null;
}

// GET_DESCRIPTOR(CONFIGURATION 0), USB 2.0 §9.4.3.
async function configurationDescriptor(device) {
  const setup = { requestType: 'standard', recipient: 'device', request: 6, value: 0x0200, index: 0 };
  const r = await bounded(device.controlTransferIn(setup, 1024), 5000, 'the configuration descriptor');
  if (r.status !== 'ok') throw new Error(`the board refused its configuration descriptor (${r.status})`);
  return new Uint8Array(r.data.buffer, r.data.byteOffset, r.data.byteLength);
}

async function go() {
  const status = $('flash-status');
  const error = $('flash-error');
  error.textContent = '';
  if (!$('image-file').files[0] && !carried) { error.textContent = 'choose the image first (.bin, .hex or the ELF)'; return; }
  let device;
  try {
    device = await navigator.usb.requestDevice({ filters: [ROM] });
    const usb = (what, p) => bounded(p, 5000, what);
    await usb('open', device.open());
    if (!device.configuration) await usb('select configuration', device.selectConfiguration(1));
    const alt = findFlash(device);
    if (!alt) throw new Error('this device has no "@Internal Flash" DFU interface: not the STM32 ROM bootloader');
    await usb('claim', device.claimInterface(alt.interfaceNumber));
    await usb('select alternate', device.selectAlternateInterface(alt.interfaceNumber, alt.alternate));
    // the layout is the alternate's name; wTransferSize, the version and
    // what it can do are in its functional descriptor, checked as
    // `polyturn flash` checks them
    const functional = functionalDescriptor(await configurationDescriptor(device)) ?? new Uint8Array();
    const { name, bytes } = await image();
    const plan = (await load()).flash_plan(name, bytes, alt.name, functional);
    status.textContent = `image ${plan.version ?? ''}, ${plan.image_len} bytes, sha256 ${plan.sha256.slice(0, 16)}…`;
    const r = await flash(webusb(device, alt.interfaceNumber), plan, ({ phase, done, total }) => {
      $('flash-progress').value = done / total;
      status.textContent = `${phase}: ${done} of ${total}`;
    });
    status.textContent = `written and verified (${plan.image_len} bytes); the board ${r.left === 'manifest' ? 'left DFU' : 'restarted'}: it runs the new firmware`;
  } catch (e) {
    error.textContent = `error: ${e.message ?? e}`;
  } finally {
    try { await bounded(device?.close() ?? Promise.resolve(), 2000, 'close'); } catch { /* it may have left the bus */ }
  }
}
