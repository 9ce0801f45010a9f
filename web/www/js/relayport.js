// The board relayed by `polyturn web --board PORT` (host-sim/src/cli/web/
// relay.rs), behind a WebSerial-shaped port, so that serial.js's Session
// speaks to it as to a port of its own: the board's lines come in as
// bytes, each line the Session writes goes out as one message. The relay
// checks every line as `polyturn device` would and refuses `dfu`; one page
// has control, the others watch (`onControl`). When the board goes away
// the port's stream ends and `goneWhy` says why; nothing is sent again.

const OPEN_MS = 5000;
// A reply's wait through the relay: the board's own answer plus a network
// hop (Wi-Fi to a tablet); serial.js waits 2 s on a port of its own.
const REPLY_MS = 5000;

export function relayed() {
  return fetch('index.html', { method: 'HEAD' }).then((r) => r.headers.get('X-Polyturn-Board') === 'relay', () => false);
}

export function relayPort({ onControl = () => {}, onNotice = () => {} } = {}) {
  const url = new URL('relay', location.href);
  url.protocol = location.protocol === 'https:' ? 'wss:' : 'ws:';
  url.search = ''; // the token, if asked, goes in the cookie the page's address set
  const ws = new WebSocket(url);
  const encoder = new TextEncoder();
  const decoder = new TextDecoder();
  let feed = null;
  const port = {
    name: '', goneWhy: '', control: null,
    readable: new ReadableStream({ start(c) { feed = c; } }),
    writable: new WritableStream({
      write(chunk) {
        for (const line of decoder.decode(chunk).split('\n')) {
          if (line.trim()) ws.send(JSON.stringify({ t: 'line', line: line.replace(/\r$/, '') }));
        }
      },
    }),
    async open() {},
    async close() { ws.close(); },
    getInfo() { return { relay: true, timeoutMs: REPLY_MS }; },
    take() { ws.send(JSON.stringify({ t: 'take' })); },
  };
  const end = (why) => {
    if (port.goneWhy) return;
    port.goneWhy = why;
    try { feed.close(); } catch { /* already closed */ }
  };
  return new Promise((resolve, reject) => {
    const timer = setTimeout(() => { reject(new Error(`polyturn web did not answer within ${OPEN_MS} ms`)); ws.close(); }, OPEN_MS);
    ws.onmessage = (e) => {
      const m = JSON.parse(e.data);
      if (m.t === 'line') feed.enqueue(encoder.encode(`${m.line}\n`));
      else if (m.t === 'hello') port.name = m.port;
      else if (m.t === 'notice') onNotice(m.why);
      else if (m.t === 'control') {
        port.control = { yours: m.yours, free: m.free };
        clearTimeout(timer);
        resolve(port);
        onControl(port.control);
      } else if (m.t === 'gone') {
        clearTimeout(timer);
        reject(new Error(m.why));
        end(m.why);
      }
    };
    ws.onclose = () => {
      clearTimeout(timer);
      reject(new Error('polyturn web closed the connection (has it stopped?)'));
      end('the connection to polyturn web closed (has it stopped?)');
    };
  });
}
