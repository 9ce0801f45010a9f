// The STM32 ROM bootloader's DfuSe (AN3156) over WebUSB: the requests of
// `polyturn flash` (host-sim/src/flash/dfuse*.rs), in the same order, on
// a plan the host library made (`flash_plan`: the image checked, padded to
// whole transfers, the pages to erase, none past the settings). Every wait
// for the device is bounded: WebUSB transfers have no timeout of their own
// (whatwg/usb#25), so each races a timer. Tested against the fake ROM in
// WebAssembly.
export const DNLOAD = 1, UPLOAD = 2, GETSTATUS = 3, CLRSTATUS = 4, ABORT = 6;
// DFU 1.1 §6.1.2 bState
export const IDLE = 2, DNLOAD_SYNC = 3, DNBUSY = 4, DNLOAD_IDLE = 5, MANIFEST = 7, UPLOAD_IDLE = 9, ERROR = 10;
// a 128 KiB sector erase takes up to 4 s (DS10314), and the ROM may hold
// back its GETSTATUS answer until the erase ends
const STEP_MS = 10000;
const POLL_MAX_MS = 1000;
const STATUS = ['OK', 'errTARGET', 'errFILE', 'errWRITE', 'errERASE', 'errCHECK_ERASED', 'errPROG', 'errVERIFY',
  'errADDRESS', 'errNOTDONE', 'errFIRMWARE', 'errVENDOR', 'errUSBR', 'errPOR', 'errUNKNOWN', 'errSTALLEDPKT'];

const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
const le32 = (v) => [v & 0xff, (v >>> 8) & 0xff, (v >>> 16) & 0xff, (v >>> 24) & 0xff];
const hex = (v) => `0x${v.toString(16).padStart(8, '0')}`;

// A transfer's promise, or an error once `ms` pass without an answer.
export function bounded(promise, ms, what) {
  let timer;
  const late = new Promise((_, reject) => {
    timer = setTimeout(() => reject(new Error(`no answer to ${what} within ${ms / 1000} s: unplug the board and start again`)), ms);
  });
  return Promise.race([promise, late]).finally(() => clearTimeout(timer));
}

// A stall is the device refusing a request; other failures are the bus
// (or the device leaving it).
export class Stall extends Error {}

// A WebUSB device's DFU interface as the two transfers DfuSe needs.
export function webusb(device, interfaceNumber) {
  const setup = (request, value) => ({ requestType: 'class', recipient: 'interface', request, value, index: interfaceNumber });
  return {
    async controlIn(request, value, length) {
      const r = await device.controlTransferIn(setup(request, value), length);
      if (r.status !== 'ok') throw new Stall(`stall (${r.status})`);
      return new Uint8Array(r.data.buffer, r.data.byteOffset, r.data.byteLength);
    },
    async controlOut(request, value, data) {
      const r = await device.controlTransferOut(setup(request, value), data);
      if (r.status !== 'ok') throw new Stall(`stall (${r.status})`);
      return r.bytesWritten;
    },
  };
}

class Dfu {
  constructor(t, stepMs) { this.t = t; this.stepMs = stepMs; }

  async usb(step, f) {
    try {
      return await bounded(f(), this.stepMs, 'the request');
    } catch (e) {
      const err = new Error(`USB transfer failed during ${step}: ${e.message ?? e}`);
      err.stall = e instanceof Stall;
      throw err;
    }
  }

  // DFU_GETSTATUS: {status, pollMs, state}
  async status(step) {
    const b = await this.usb(step, () => this.t.controlIn(GETSTATUS, 0, 6));
    if (b.length < 6) throw new Error(`${step}: a status of ${b.length} bytes, not 6`);
    return { status: b[0], pollMs: b[1] | (b[2] << 8) | (b[3] << 16), state: b[4] };
  }

  // Back to dfuIDLE from wherever an earlier session left the device.
  async toIdle(step) {
    for (let i = 0; i < 3; i++) {
      const s = await this.status(step);
      if (s.state === IDLE) return;
      if (s.state === ERROR) await this.usb(step, () => this.t.controlOut(CLRSTATUS, 0, new Uint8Array()));
      else if (s.state === DNLOAD_IDLE || s.state === UPLOAD_IDLE) await this.usb(step, () => this.t.controlOut(ABORT, 0, new Uint8Array()));
      else throw new Error(`${step}: the bootloader is in state ${s.state}, not idle`);
    }
    throw new Error(`${step}: the bootloader would not return to idle`);
  }

  // Polls until the request is done (AN3156: it runs at the first
  // GETSTATUS), at most stepMs. Done is dfuDNLOAD-IDLE with status OK
  // (AN2662 §4.5.2), as dfu-core's wait (`polyturn flash`) requires.
  async wait(step) {
    const t0 = performance.now();
    for (;;) {
      const s = await this.status(step);
      if (s.state === ERROR) {
        // leave it idle for the next try, as `polyturn flash` does
        await this.usb(step, () => this.t.controlOut(CLRSTATUS, 0, new Uint8Array())).catch(() => {});
        throw new Error(`the bootloader refused ${step}: ${STATUS[s.status] ?? s.status}`);
      }
      if (s.state === DNLOAD_IDLE && s.status === 0) return;
      if (s.state !== DNBUSY && s.state !== DNLOAD_SYNC) {
        throw new Error(`${step}: the bootloader went to state ${s.state} (${STATUS[s.status] ?? s.status}), not dfuDNLOAD-IDLE`);
      }
      const waited = performance.now() - t0;
      if (waited > this.stepMs) throw new Error(`${step}: the bootloader was still busy after ${Math.round(waited)} ms`);
      await sleep(Math.min(s.pollMs, POLL_MAX_MS));
    }
  }

  async command(code, address, step) {
    await this.usb(step, () => this.t.controlOut(DNLOAD, 0, new Uint8Array([code, ...le32(address)])));
    await this.wait(step);
  }
}

// Erases, writes, reads everything back and compares, then leaves DFU.
// `progress({phase, done, total})`; `stepMs` bounds each request and each
// wait. Resolves to {left: 'manifest'|'vanished'}.
export async function flash(t, plan, progress = () => {}, { stepMs = STEP_MS } = {}) {
  const d = new Dfu(t, stepMs);
  const base = plan.pages[0];
  const { bytes, transfer } = plan;
  const blocks = bytes.length / transfer;
  await d.toIdle('the start');
  for (const [i, page] of plan.pages.entries()) {
    await d.command(0x41, page, `the erase of sector ${i} at ${hex(page)}`);
    progress({ phase: 'erase', done: i + 1, total: plan.pages.length });
  }
  await d.command(0x21, base, 'the write address');
  for (let n = 0; n < blocks; n++) {
    const step = `the write at ${hex(base + n * transfer)}`;
    const chunk = bytes.subarray(n * transfer, (n + 1) * transfer);
    const sent = await d.usb(step, () => t.controlOut(DNLOAD, n + 2, chunk));
    if (sent !== chunk.length) throw new Error(`${step}: the bootloader took ${sent} of ${chunk.length} bytes`);
    await d.wait(step);
    progress({ phase: 'write', done: (n + 1) * transfer, total: bytes.length });
  }
  await verify(d, plan, progress);
  progress({ phase: 'leave', done: 1, total: 1 });
  return leave(d, base);
}

async function verify(d, { bytes, transfer, pages }, progress) {
  const base = pages[0];
  await d.command(0x21, base, 'the read-back address');
  await d.usb('the read-back', () => d.t.controlOut(ABORT, 0, new Uint8Array()));
  for (let n = 0; n < bytes.length / transfer; n++) {
    const address = base + n * transfer;
    const step = `the read-back at ${hex(address)}`;
    const got = await d.usb(step, () => d.t.controlIn(UPLOAD, n + 2, transfer));
    if (got.length !== transfer) {
      await d.usb(step, () => d.t.controlOut(ABORT, 0, new Uint8Array())).catch(() => {});
      throw new Error(`${step}: the bootloader sent ${got.length} of ${transfer} bytes`);
    }
    const wrote = bytes.subarray(n * transfer, (n + 1) * transfer);
    const k = wrote.findIndex((w, i) => w !== got[i]);
    if (k >= 0) {
      await d.usb(step, () => d.t.controlOut(ABORT, 0, new Uint8Array())).catch(() => {});
      throw new Error(`verify failed at ${hex(address + k)}: wrote 0x${wrote[k].toString(16).padStart(2, '0')}, read back 0x${got[k].toString(16).padStart(2, '0')}`);
    }
    progress({ phase: 'verify', done: (n + 1) * transfer, total: bytes.length });
  }
  await d.usb('the end of the read-back', () => d.t.controlOut(ABORT, 0, new Uint8Array()));
}

// AN3156 §5.5: the address of the start, then a zero-length DNLOAD; the
// ROM answers dfuMANIFEST and jumps, or leaves the bus at once (so a bus
// failure, as in dfu-util's dfuse_do_leave, is it gone). A stall is a
// refusal, and no answer at all is not known to be a leave: both errors.
async function leave(d, base) {
  await d.command(0x21, base, 'the start address');
  const gone = (e) => {
    if (e.stall || /no answer to/.test(e.message)) throw e;
    return { left: 'vanished' };
  };
  try {
    await d.usb('the leave request', () => d.t.controlOut(DNLOAD, 2, new Uint8Array()));
  } catch (e) {
    return gone(e);
  }
  let s;
  try {
    s = await d.status('the leave request');
  } catch (e) {
    return gone(e);
  }
  if (s.state === MANIFEST) return { left: 'manifest' };
  throw new Error(`the leave request: the bootloader stayed in state ${s.state} (${STATUS[s.status] ?? s.status})`);
}
