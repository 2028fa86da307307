// The page's WebSocket, received on a Worker's thread. A state frame of 10^4 bodies is 1 MB, and a
// WebSocket on the page's main thread takes it in chunks between rendered frames: with software
// rendering at a few frames a second that took seconds per state (bench/view/README.md). The
// Worker receives whole messages on its own thread and hands each ArrayBuffer over without a copy.
// WorkerSocket has the part of WebSocket's interface app.js uses (readyState, send, close,
// onopen, onclose, onmessage with event.data), and event.receivedAt: the worker's receipt of a
// binary frame (ms since the epoch, as performance.timeOrigin + performance.now()).

// The worker: one WebSocket; text frames and binary frames (transferred) to the page, the page's
// texts to rigid-view. Each binary frame carries the wall clock (ms) when the worker received it:
// the page splits its publish-to-frame latency there (bench/view).
const kWorker = `
let ws = null;
onmessage = (e) => {
  if (e.data.open) {
    ws = new WebSocket(e.data.open);
    ws.binaryType = 'arraybuffer';
    ws.onopen = () => postMessage({ open: true });
    ws.onclose = () => postMessage({ close: true });
    ws.onmessage = (m) => {
      if (m.data instanceof ArrayBuffer) {
        postMessage({ data: m.data, at: performance.timeOrigin + performance.now() }, [m.data]);
      }
      else postMessage({ data: m.data });
    };
  } else if (typeof e.data.send === 'string' && ws && ws.readyState === 1) {
    ws.send(e.data.send);
  } else if (e.data.close && ws) {
    ws.close();
  }
};
`;
let workerUrl = null;

export class WorkerSocket {
  constructor(url) {
    this.readyState = 0;  // CONNECTING, as WebSocket
    this.onopen = null;
    this.onclose = null;
    this.onmessage = null;
    workerUrl ||= URL.createObjectURL(new Blob([kWorker], { type: 'text/javascript' }));
    this.worker = new Worker(workerUrl);
    this.worker.onmessage = (e) => {
      const m = e.data;
      if (m.open) {
        this.readyState = 1;
        if (this.onopen) this.onopen();
      } else if (m.close) {
        this.shut();
      } else if (this.onmessage) {
        this.onmessage({ data: m.data, receivedAt: m.at });
      }
    };
    this.worker.onerror = () => this.shut();
    this.worker.postMessage({ open: url });
  }

  send(text) {
    if (this.readyState === 1) this.worker.postMessage({ send: String(text) });
  }

  close() {
    this.worker.postMessage({ close: true });
  }

  shut() {
    if (this.readyState === 3) return;
    this.readyState = 3;  // CLOSED
    this.worker.terminate();
    if (this.onclose) this.onclose();
  }
}
