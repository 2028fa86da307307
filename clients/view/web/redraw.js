// Draw on change: whether an animation frame must render the 3D view, or may leave the canvas as
// it is (the last frame stays on the screen, and preserveDrawingBuffer keeps it readable).
//
// Why: where WebGL runs on the CPU (SwiftShader: headless Chromium, machines without a GPU) every
// frame costs its pixels, whether anything moved or not: a page left open on a paused scene drew
// 60 identical frames a second, a core's worth of CPU on the machine rigidd runs on
// (bench/notes/view-bench.md, "Draw on change"). A renderer that draws only on change is what desktop
// tools do (an editor's viewport, Foxglove's panels); a view of a running simulation changes
// every state, so while the scene moves nothing is skipped.
//
// How: whatever changes the picture (a state whose poses differ from the last one's, the camera,
// the pointer, a new scene, a resize, a control on the page) calls wake(now); every frame up to
// `linger` ms later is drawn (OrbitControls' damping, a hover's pick and other consequences of
// one input settle within it; the page calls wake again while they go on). Past that, a frame is
// drawn only every `heartbeat` ms: a change that no wake reported shows within a second instead
// of never.
export class Redraw {
  constructor({ linger = 250, heartbeat = 1000 } = {}) {
    if (!(Number.isFinite(linger) && linger >= 0)) throw new RangeError(`Redraw: linger must be >= 0 ms, got ${linger}`);
    if (!(Number.isFinite(heartbeat) && heartbeat > 0))
      throw new RangeError(`Redraw: heartbeat must be > 0 ms, got ${heartbeat}`);
    this.linger = linger;
    this.heartbeat = heartbeat;
    this.until = -Infinity;     // ms: frames up to here are drawn
    this.lastDrawn = -Infinity;  // ms: the last frame drawn
    // Frames so far (the page's debug counters): drawn, and skipped as unchanged.
    this.drawn = 0;
    this.skipped = 0;
  }

  // Something the picture shows changed at `now` (ms, performance.now()'s clock).
  wake(now) {
    if (now + this.linger > this.until) this.until = now + this.linger;
  }

  // One call per animation frame with its timestamp (ms): whether to draw it. A frame drawn
  // counts as such from here on (the heartbeat's next one is a heartbeat later).
  due(now) {
    if (now <= this.until || !(now - this.lastDrawn < this.heartbeat)) {
      this.lastDrawn = now;
      ++this.drawn;
      return true;
    }
    ++this.skipped;
    return false;
  }
}
