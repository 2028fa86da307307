// Dynamic resolution: the fraction of the device pixel ratio the page renders at, chosen so that
// it draws a frame at every refresh of a 60 Hz (or faster) display.
//
// Why: where WebGL runs on the CPU (SwiftShader: headless Chromium, machines without a GPU) a
// frame's cost is mostly per pixel, and a page that misses refreshes moves in visible jerks,
// which matter more in a view of motion than its sharpness: a slightly lower scale gives back every
// refresh (bench/notes/view.md, view-bench.md). With a GPU the page stays at 1.
//
// How, one decision per second of frames:
// - `lowerAfter` seconds in a row with fewer than `slowFps` frames each (more than two refreshes
//   missed at 60 Hz) lower the scale. Two seconds, not one: a page that cannot draw at its scale
//   is slow every second, while one stall of the machine (another process, a collection) makes
//   one slow second, which is no reason to draw every later frame blurred. By `step`, or further
//   where the page is far too slow, down to `min`: a software renderer's frame costs per pixel,
//   the pixels go as the scale squared, so the scale goes by sqrt(T / c), T = 1000 / fastFps ms
//   the frame time wanted and c the frame's cost, its mean interval less half a refresh (paced
//   frames end at a refresh: a frame of T + 1 ms takes two): a page far too slow gets there in
//   one decision instead of descending step by step for seconds (bench/notes/view.md);
// - after `raiseAfter` seconds in a row of at least `fastFps` frames (none missed) it raises it
//   again by one step, to 1 at most: a probe, since a paced page shows no headroom;
// - a probe that fails (the scale lowered within `probeWindow` seconds of the raise) doubles the
//   wait before the next probe, up to `maxRaiseAfter`, so that a page at its limit spends its
//   time at the scale it can draw, not oscillating around it (as TCP backs off its probes).
// A new scene starts again from 1 with the first wait (reset).
export class RenderScale {
  constructor({ min = 0.25, step = 0.75, slowFps = 57.5, fastFps = 58.5, lowerAfter = 2,
                raiseAfter = 30, maxRaiseAfter = 480, probeWindow = 30 } = {}) {
    const ok = (x) => Number.isFinite(x);
    if (!(ok(min) && min > 0 && min <= 1)) throw new RangeError(`RenderScale: min must be in (0, 1], got ${min}`);
    if (!(ok(step) && step > 0 && step < 1)) throw new RangeError(`RenderScale: step must be in (0, 1), got ${step}`);
    if (!(ok(slowFps) && ok(fastFps) && slowFps > 0 && fastFps >= slowFps))
      throw new RangeError(`RenderScale: need 0 < slowFps <= fastFps, got ${slowFps}, ${fastFps}`);
    if (!(Number.isInteger(lowerAfter) && lowerAfter >= 1))
      throw new RangeError(`RenderScale: lowerAfter must be an integer >= 1, got ${lowerAfter}`);
    if (!(Number.isInteger(raiseAfter) && raiseAfter >= 1 && Number.isInteger(maxRaiseAfter) &&
          maxRaiseAfter >= raiseAfter))
      throw new RangeError(`RenderScale: need integers 1 <= raiseAfter <= maxRaiseAfter, got ${raiseAfter}, ${maxRaiseAfter}`);
    if (!(ok(probeWindow) && probeWindow >= 0)) throw new RangeError(`RenderScale: probeWindow must be >= 0, got ${probeWindow}`);
    Object.assign(this, { min, step, slowFps, fastFps, lowerAfter, firstRaiseAfter: raiseAfter,
                          maxRaiseAfter, probeWindow });
    this.reset();
    // Decisions so far (the bench and the tests read them): lowered, raised, failed probes.
    this.lowered = 0;
    this.raised = 0;
    this.failedProbes = 0;
  }

  // Back to full resolution and the first wait; the next frame starts a new window.
  reset() {
    this.scale = 1;
    this.raiseAfter = this.firstRaiseAfter;
    this.windowStart = null;
    this.frames = 0;
    this.fastRun = 0;
    this.slowRun = 0;
    this.lastRaise = null;  // ms, of the last probe
  }

  // One call per animation frame with its timestamp (ms) and whether the page is shown (a hidden
  // page gets no frames to count, so its window starts again). Returns the scale to render at.
  frame(now, visible = true) {
    if (this.windowStart === null || !visible || !(now >= this.windowStart)) {
      this.windowStart = now;
      this.frames = 0;
      this.slowRun = 0;
      return this.scale;
    }
    ++this.frames;
    const elapsed = now - this.windowStart;
    if (elapsed < 1000) return this.scale;
    const fps = (this.frames * 1000) / elapsed;
    this.windowStart = now;
    this.frames = 0;
    if (fps < this.slowFps) {
      this.fastRun = 0;
      if (++this.slowRun < this.lowerAfter) return this.scale;
      this.slowRun = 0;
      if (this.lastRaise !== null && now - this.lastRaise <= this.probeWindow * 1000) {
        this.raiseAfter = Math.min(this.maxRaiseAfter, 2 * this.raiseAfter);
        ++this.failedProbes;
        this.lastRaise = null;
      }
      const wanted = 1000 / this.fastFps, cost = 1000 / fps - wanted / 2;
      const lower = Math.max(this.min, this.scale * Math.min(this.step, Math.sqrt(wanted / cost)));
      if (lower < this.scale) {
        this.scale = lower;
        ++this.lowered;
      }
    } else if (fps >= this.fastFps) {
      this.slowRun = 0;
      if (this.scale < 1 && ++this.fastRun >= this.raiseAfter) {
        this.fastRun = 0;
        // (1 exactly once within a step of it, so that a raise from the first step down lands on 1.)
        const up = this.scale / this.step;
        this.scale = up > 1 - 1e-9 ? 1 : up;
        this.lastRaise = now;
        ++this.raised;
      }
    } else {
      this.fastRun = 0;
      this.slowRun = 0;
    }
    return this.scale;
  }
}
