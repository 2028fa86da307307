// The page's WebSocket, received on a Worker's thread. A state frame of 10^4 bodies is 1 MB, and a
// WebSocket on the page's main thread takes it in chunks between rendered frames: with software
// rendering at a few frames a second that took seconds per state (bench/notes/view-bench.md). The
// Worker receives whole messages on its own thread and hands each ArrayBuffer over without a copy.
// WorkerSocket has the part of WebSocket's interface connection.js uses (readyState, send, close,
// onopen, onclose, onmessage with event.data), and for a binary frame the worker's receipt by two
// clocks, where the page splits its publish-to-frame latency (bench/view): event.receivedWall,
// Date.now(), to compare with rigidd's stamp (this host's CLOCK_REALTIME, read when it happens), and
// event.receivedAt, performance.timeOrigin + performance.now(), to compare with the page's own
// performance clock. (timeOrigin is the wall clock once, when the context starts: where the wall
// clock is being slewed, as a VM's can be by milliseconds a second, the two drift apart.)

// The worker: one WebSocket; text frames and binary frames (transferred) to the page, the page's
// texts to rigid-view. Each binary frame carries the clocks of its receipt (above).
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
        postMessage({ data: m.data, at: performance.timeOrigin + performance.now(), wall: Date.now() },
                    [m.data]);
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
        this.onmessage({ data: m.data, receivedAt: m.at, receivedWall: m.wall });
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
