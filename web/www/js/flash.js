// Flash: a release image to a board in ROM DFU mode over WebUSB
// (Chromium), checked and planned by the host library first.
import { load } from './polyturn.js';
import { flash, webusb } from './dfu.js';

const $ = (id) => document.getElementById(id);
// AN2606: the STM32 ROM bootloader's USB DFU
const ROM = { vendorId: 0x0483, productId: 0xdf11 };

export function init() {
  const supported = 'usb' in navigator;
  $('usb-support').textContent = supported
    ? 'Chromium, Chrome or Edge: WebUSB finds the board in DFU mode (on Linux a udev rule may be needed, see the manual).'
    : 'This browser has no WebUSB: use Chromium, Chrome or Edge, or `polyturn flash`.';
  $('flash-go').disabled = !supported;
  $('flash-go').addEventListener('click', go);
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

async function go() {
  const file = $('image-file').files[0];
  const status = $('flash-status');
  const error = $('flash-error');
  error.textContent = '';
  if (!file) { error.textContent = 'choose the image first (.bin, .hex or the ELF)'; return; }
  let device;
  try {
    device = await navigator.usb.requestDevice({ filters: [ROM] });
    await device.open();
    if (!device.configuration) await device.selectConfiguration(1);
    const alt = findFlash(device);
    if (!alt) throw new Error('this device has no "@Internal Flash" DFU interface: not the STM32 ROM bootloader');
    await device.claimInterface(alt.interfaceNumber);
    await device.selectAlternateInterface(alt.interfaceNumber, alt.alternate);
    // the ROM's wTransferSize is 2048 (AN3156 §4); the layout is its name
    const plan = (await load()).flash_plan(file.name, new Uint8Array(await file.arrayBuffer()), alt.name, 2048);
    status.textContent = `image ${plan.version ?? ''}, ${plan.image_len} bytes, sha256 ${plan.sha256.slice(0, 16)}…`;
    const r = await flash(webusb(device, alt.interfaceNumber), plan, ({ phase, done, total }) => {
      $('flash-progress').value = done / total;
      status.textContent = `${phase}: ${done} of ${total}`;
    });
    status.textContent = `written and verified (${plan.image_len} bytes); the board ${r.left === 'manifest' ? 'left DFU' : 'restarted'}: it runs the new firmware`;
  } catch (e) {
    error.textContent = `error: ${e.message ?? e}`;
  } finally {
    try { await device?.close(); } catch { /* it may have left the bus */ }
  }
}
