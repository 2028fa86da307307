// What the page measures of itself, for bench/view (window.rigidView): the last kKept latencies
// (ms) from rigidd's publish to the rendered frame that draws the state, and their parts: publish
// to the worker's receipt (rigidd, the bus, rigid-view, the WebSocket), on to the main thread
// applying it (the hand-over, then the wait for the next frame's start), on to the end of that
// frame (renders it); the drawn frames' timestamps (bench/view counts the refreshes missed); the
// time spent rendering and applying states.
const kKept = 4096;

export class Timings {
  constructor() {
    this.latencies = new Float64Array(kKept);
    this.parts = { toWorker: new Float64Array(kKept), toMain: new Float64Array(kKept),
                   toFrame: new Float64Array(kKept) };
    this.latencyCount = 0;
    this.frameTimes = new Float64Array(kKept);
    this.frameCount = 0;
    this.renderMs = 0;  // total time in renderer.render (the GPU's work may finish later)
    this.stateMs = 0;   // total time applying states
    // rigidd's stamp (ms, its CLOCK_REALTIME: this host's) of the state applied and not yet drawn.
    this.pendingStampMs = null;
    // Wall clock (Date.now(), ms) of the last state's receipt on the worker, and the performance
    // clock (timeOrigin + now) there and on the main thread: { wall, worker, main }
    // (worker_socket.js).
    this.arrival = null;
  }

  // A state applied: its frame (from the socket), its stamp (BigInt ns, 0: none) and when the main
  // thread started on it (performance.now()).
  stateApplied(event, stampNs, startedAt) {
    if (stampNs > 0n) this.pendingStampMs = Number(stampNs / 1000n) / 1000;
    this.arrival = { wall: event.receivedWall, worker: event.receivedAt, main: performance.timeOrigin + startedAt };
  }

  frameDrawn(now) {
    this.frameTimes[this.frameCount++ % kKept] = now;
  }

  // The end of an animation frame: the latency of the state it drew, if it drew one.
  frameEnded(drawn) {
    if (!drawn) this.pendingStampMs = null;  // a state that changed nothing drawn: no latency
    if (this.pendingStampMs === null) return;
    // Against rigidd's stamp, the wall clock now (1 ms steps); within the page, its own clocks.
    const now = performance.timeOrigin + performance.now(), k = this.latencyCount++ % kKept;
    this.latencies[k] = Date.now() - this.pendingStampMs;
    const a = this.arrival && Number.isFinite(this.arrival.worker) ? this.arrival : { wall: NaN, worker: NaN, main: NaN };
    this.parts.toWorker[k] = a.wall - this.pendingStampMs;
    this.parts.toMain[k] = a.main - a.worker;
    this.parts.toFrame[k] = now - a.main;
    this.pendingStampMs = null;
  }

  latencyList() {
    return Array.from(this.latencies.subarray(0, Math.min(this.latencyCount, kKept)));
  }

  latencyParts() {
    return Object.fromEntries(Object.entries(this.parts).map(
      ([k, a]) => [k, Array.from(a.subarray(0, Math.min(this.latencyCount, kKept)))]));
  }

  clearLatencies() {
    this.latencyCount = 0;
  }

  frameTimeList() {
    const n = Math.min(this.frameCount, kKept), first = this.frameCount - n;
    return Array.from({ length: n }, (_, i) => this.frameTimes[(first + i) % kKept]);
  }
}
