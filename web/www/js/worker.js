// The simulation's worker: the simulator (with the real sync core) runs
// here, so the page stays responsive through a long run.
import init, { run } from '../pkg/polyturn_web.js';

const ready = init();

self.onmessage = async (e) => {
  await ready;
  const t0 = performance.now();
  try {
    const r = JSON.parse(run(e.data.args));
    self.postMessage({ ok: true, out: r.out, svg: r.files['sim.svg'], ms: performance.now() - t0 });
  } catch (err) {
    self.postMessage({ ok: false, error: String(err) });
  }
};
