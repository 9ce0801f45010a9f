// One console session over a WebSerial port, as `polyturn device` speaks
// it (host-sim/src/cli/device/session.rs): each command goes out with a tag
// (`#N cmd`), and its reply is the line with the same tag that reads as a
// reply (`ok`, `ok ...`, `error: ...`: the library's `is_reply`), so a port
// that echoes the command is never taken for the board; any other line
// with the tag is an error quoting it. Every wait has a deadline and every
// line a length bound; other lines (watch's status) go to `onLine`.
import { load } from './polyturn.js';

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
    // a port may ask for longer (the relay: a network hop on top)
    s.timeoutMs = port.getInfo?.().timeoutMs ?? TIMEOUT_MS;
    await port.open({ baudRate: 115200 });
    s.reader = port.readable.getReader();
    s.writer = port.writable.getWriter();
    const lib = await load();
    s.commandMax = lib.command_max();
    s.replyMax = lib.reply_max();
    s.isReply = lib.is_reply;
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
          const l = pending.slice(0, nl).replace(/\r$/, '');
          pending = pending.slice(nl + 1);
          if (l.length > this.replyMax) this.fail(`the board sent a line longer than ${this.replyMax} bytes: not a polyturn console`);
          else this.line(l);
        }
        if (pending.length > this.replyMax) { // not a polyturn line
          pending = '';
          this.fail(`the board sent a line longer than ${this.replyMax} bytes: not a polyturn console`);
        }
      }
    } finally {
      this.fail('the board closed the port before replying');
      this.onClose();
    }
  }

  line(l) {
    const w = this.waiting;
    if (w && l === w.sent) {
      w.echoed = true; // our own line, echoed by the port
      return;
    }
    const m = /^#(\d+) (.*)$/.exec(l);
    if (m && w && Number(m[1]) === w.tag) {
      this.waiting = null;
      if (this.isReply(m[2])) w.resolve(m[2]);
      else w.reject(new Error(`the board answered '${w.command.split(' ')[0]}' with '${l.slice(0, 80)}': neither ok nor error, not a polyturn reply`));
    } else if (l.length) {
      this.onLine(l);
    }
  }

  // Ends the command waiting, if any, with `why`.
  fail(why) {
    const w = this.waiting;
    this.waiting = null;
    if (w) w.reject(new Error(why));
  }

  // Sends one command; resolves to the reply (`ok ...`), rejects with the
  // board's `error: ...` or a timeout. Commands go one at a time.
  ask(command, timeoutMs = this.timeoutMs ?? TIMEOUT_MS) {
    const run = () => this.send(command, timeoutMs);
    const p = this.queue.then(run, run);
    this.queue = p.catch(() => {});
    return p;
  }

  async send(command, timeoutMs) {
    if (/[^\x20-\x7e]/.test(command)) throw new Error(`the command '${command}' holds a character the board does not take`);
    if (command.length > this.commandMax) throw new Error(`the command is ${command.length} characters long: the board takes at most ${this.commandMax}`);
    if (this.isReply(command)) throw new Error(`the command '${command}' reads as a reply: not sent`);
    this.tag = this.tag % 999999 + 1;
    const tag = this.tag;
    const sent = `#${tag} ${command}`;
    const reply = new Promise((resolve, reject) => {
      const w = { tag, sent, command, echoed: false };
      const timer = setTimeout(() => {
        this.waiting = null;
        const echo = w.echoed ? ': the port echoed the command back (a terminal in echo mode, a loopback or an adapter), not a polyturn board' : '';
        reject(new Error(`no reply to '${command.split(' ')[0]}' within ${timeoutMs} ms${echo}`));
      }, timeoutMs);
      w.resolve = (r) => { clearTimeout(timer); resolve(r); };
      w.reject = (e) => { clearTimeout(timer); reject(e); };
      this.waiting = w;
    });
    await this.writer.write(new TextEncoder().encode(`${sent}\n`));
    const r = await reply;
    if (r.startsWith('error: ')) throw new Error(r);
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
