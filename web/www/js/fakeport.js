// A simulated board behind a WebSerial-shaped port: the real sync core's
// console and controller in WebAssembly (`FakeBoard`), with a machine
// model letting time pass. The page offers it to try the device panel
// without a board; the page's tests put it behind `navigator.serial`.
import { load } from './polyturn.js';

const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
const WATCH_MS = 100; // the firmware's 10 Hz

export async function fakeSerialPort() {
  const board = new (await load()).FakeBoard();
  let closed = false;
  let lastStatus = 0;
  const readable = new ReadableStream({
    async pull(controller) {
      for (;;) {
        if (closed) return controller.close();
        const replies = board.read();
        if (replies.length) return controller.enqueue(replies);
        if (performance.now() - lastStatus >= WATCH_MS) {
          lastStatus = performance.now();
          const status = board.watch_line();
          if (status.length) return controller.enqueue(status);
        }
        await sleep(10);
      }
    },
  });
  const writable = new WritableStream({ write(chunk) { board.write(chunk); } });
  return {
    board,
    readable,
    writable,
    async open() {},
    async close() { closed = true; },
    getInfo() { return { simulated: true }; },
  };
}
