// One console session over a WebSerial port, as `polyturn device` speaks
// it (host-sim/src/cli/device/session.rs): each command goes out with a tag
// (`#N cmd`), only the line with the same tag is its reply, every wait has
// a deadline and every line a length bound; other lines (watch's status)
// go to `onLine`.
import { load } from './polyturn.js';

const REPLY_MAX = 512; // longest line taken from the board
export const TIMEOUT_MS = 2000;

export class Session {
  constructor(port) {
    this.port = port;
    this.tag = Math.floor(Math.random() * 900000);
    this.waiting = null;
    this.queue = Promise.resolve();
    this.onLine = () => {};
    this.onClose = () => {};
  }

  static async open(port) {
    const s = new Session(port);
    await port.open({ baudRate: 115200 });
    s.reader = port.readable.getReader();
    s.writer = port.writable.getWriter();
    s.commandMax = (await load()).command_max();
    s.readLoop();
    return s;
  }

  async readLoop() {
    const text = new TextDecoder();
    let pending = '';
    try {
      for (;;) {
        const { value, done } = await this.reader.read();
        if (done) break;
        pending += text.decode(value, { stream: true });
        let nl;
        while ((nl = pending.indexOf('\n')) >= 0) {
          this.line(pending.slice(0, nl).replace(/\r$/, ''));
          pending = pending.slice(nl + 1);
        }
        if (pending.length > REPLY_MAX) pending = ''; // not a polyturn line
      }
    } finally {
      this.onClose();
    }
  }

  line(l) {
    const m = /^#(\d+) (.*)$/.exec(l);
    if (m && this.waiting && Number(m[1]) === this.waiting.tag) {
      this.waiting.resolve(m[2]);
      this.waiting = null;
    } else if (l.length) {
      this.onLine(l);
    }
  }

  // Sends one command; resolves to the reply (`ok ...`), rejects with the
  // board's `error: ...` or a timeout. Commands go one at a time.
  ask(command, timeoutMs = TIMEOUT_MS) {
    const run = () => this.send(command, timeoutMs);
    const p = this.queue.then(run, run);
    this.queue = p.catch(() => {});
    return p;
  }

  async send(command, timeoutMs) {
    if (/[^\x20-\x7e]/.test(command)) throw new Error(`the command '${command}' holds a character the board does not take`);
    if (command.length > this.commandMax) throw new Error(`the command is ${command.length} characters long: the board takes at most ${this.commandMax}`);
    this.tag = (this.tag + 1) % 1000000;
    const tag = this.tag;
    const reply = new Promise((resolve, reject) => {
      const timer = setTimeout(() => {
        this.waiting = null;
        reject(new Error(`no reply to '${command}' within ${timeoutMs} ms`));
      }, timeoutMs);
      this.waiting = { tag, resolve: (r) => { clearTimeout(timer); resolve(r); } };
    });
    await this.writer.write(new TextEncoder().encode(`#${tag} ${command}\n`));
    const r = await reply;
    if (r.startsWith('error')) throw new Error(r);
    return r;
  }

  async close() {
    try { await this.reader.cancel(); } catch { /* already closed */ }
    this.reader.releaseLock();
    this.writer.releaseLock();
    await this.port.close();
  }
}

// `ok a=1 b="two words"` as {a: '1', b: 'two words'}.
export function pairs(line) {
  const out = {};
  for (const m of line.matchAll(/([\w-]+)=("[^"]*"|\S+)/g)) out[m[1]] = m[2].replace(/^"|"$/g, '');
  return out;
}
