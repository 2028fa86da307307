// Headless Chromium driven over its DevTools pipe (--remote-debugging-pipe) with only the Target,
// Emulation, Page and Runtime domains: what view_bench needs (open a page at a size, evaluate
// expressions, see its uncaught errors) and nothing more. Why not playwright here: playwright
// enables the Network domain on every page and worker, so each WebSocket frame the page's worker
// receives is sent to the driver as an event (binary payloads in base64): at 10^4 bodies, 20
// frames of 320 KB a second, CPU taken from the page being measured (how much:
// bench/notes/view-bench.md). A page a person opens has no driver.
//
// launchCdp(executable, args) -> { newPage({ width, height }), close() }; a page has goto(url),
// evaluate(expression) (awaits promises, returns the value), on('pageerror', fn), close().
import { spawn } from 'node:child_process';

export async function launchCdp(executable, args) {
  const child = spawn(executable, [...args, '--remote-debugging-pipe', 'about:blank'],
                      { stdio: ['ignore', 'ignore', 'pipe', 'pipe', 'pipe'] });
  let stderr = '';
  child.stderr.on('data', (d) => { stderr = (stderr + d).slice(-4000); });
  const toBrowser = child.stdio[3], fromBrowser = child.stdio[4];
  const pending = new Map();
  const listeners = new Set();
  let nextId = 1, closed = false, received = Buffer.alloc(0);
  const fail = (why) => {
    closed = true;
    for (const { reject } of pending.values()) reject(new Error(why));
    pending.clear();
  };
  child.on('exit', (code) => fail(`chromium exited (${code}): ${stderr.slice(-500)}`));
  // Messages are JSON texts, each ended by a NUL byte.
  fromBrowser.on('data', (chunk) => {
    received = Buffer.concat([received, chunk]);
    for (let end; (end = received.indexOf(0)) >= 0;) {
      const message = JSON.parse(received.subarray(0, end).toString('utf8'));
      received = received.subarray(end + 1);
      const waiting = message.id !== undefined ? pending.get(message.id) : undefined;
      if (waiting) {
        pending.delete(message.id);
        if (message.error) waiting.reject(new Error(`${waiting.method}: ${message.error.message}`));
        else waiting.resolve(message.result);
      } else {
        for (const listener of listeners) listener(message);
      }
    }
  });
  const send = (method, params = {}, sessionId = undefined) => new Promise((resolve, reject) => {
    if (closed) return reject(new Error(`${method}: the browser is gone`));
    const id = nextId++;
    pending.set(id, { resolve, reject, method });
    toBrowser.write(JSON.stringify({ id, method, params, ...(sessionId ? { sessionId } : {}) }) + '\0');
  });
  await send('Browser.getVersion');

  return {
    pid: child.pid,  // (the bench sums its process tree's CPU time)
    async newPage({ width, height }) {
      // Each page in a window of its own: a second tab in one window would hide the first, and a
      // hidden page gets no animation frames (--rigidd-cost opens two).
      const { targetId } = await send('Target.createTarget', { url: 'about:blank', newWindow: true });
      const { sessionId } = await send('Target.attachToTarget', { targetId, flatten: true });
      const errorHandlers = [];
      const onEvent = (m) => {
        if (m.sessionId !== sessionId || m.method !== 'Runtime.exceptionThrown') return;
        const d = m.params.exceptionDetails;
        const text = (d.exception && d.exception.description) || d.text;
        for (const h of errorHandlers) h(text);
      };
      listeners.add(onEvent);
      await send('Emulation.setDeviceMetricsOverride', { width, height, deviceScaleFactor: 1, mobile: false }, sessionId);
      await send('Runtime.enable', {}, sessionId);
      const evaluate = async (expression) => {
        const r = await send('Runtime.evaluate', { expression: String(expression), returnByValue: true, awaitPromise: true }, sessionId);
        if (r.exceptionDetails) {
          const d = r.exceptionDetails;
          throw new Error(`evaluate ${expression}: ${(d.exception && d.exception.description) || d.text}`);
        }
        return r.result.value;
      };
      return {
        async goto(url) {
          await send('Page.navigate', { url }, sessionId);
          // Until the new document has loaded (the old one may answer first, or none during the swap).
          const end = Date.now() + 30000;
          for (;;) {
            const state = await evaluate(`location.href === ${JSON.stringify(url)} && document.readyState`).catch(() => null);
            if (state === 'complete') return;
            if (Date.now() > end) throw new Error(`timed out loading ${url}`);
            await new Promise((r) => setTimeout(r, 50));
          }
        },
        evaluate,
        on(event, handler) { if (event === 'pageerror') errorHandlers.push(handler); },
        async close() {
          listeners.delete(onEvent);
          await send('Target.closeTarget', { targetId }).catch(() => {});
        },
      };
    },
    async close() {
      if (!closed) await Promise.race([send('Browser.close').catch(() => {}), new Promise((r) => setTimeout(r, 3000))]);
      closed = true;
      child.kill('SIGKILL');
    },
  };
}
