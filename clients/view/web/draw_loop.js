// The page's animation loop, drawing on change (redraw.js): a frame renders only when something it
// shows changed, reported by wake(); a paused scene under a still camera costs no rendering. Nor
// animation frames: after a frame with nothing to draw the loop stops (stop), and starts again
// (ensure) on a wake, on any message from rigid-view (a state to apply and acknowledge, Stats for
// the plot) and for the heartbeat; between them Chromium calls nothing of the page 60 times a
// second.
import { Redraw } from './redraw.js';

export class DrawLoop {
  // viewport: whose renderer runs the loop (viewport.js); frame(now): one animation frame.
  constructor(viewport, frame) {
    this.viewport = viewport;
    this.frame = frame;
    this.redraw = new Redraw();
    this.looping = false;
    setInterval(() => this.ensure(), this.redraw.heartbeat / 2);
    // Any input on the page may change the picture (the camera, a hover, a checkbox, the body
    // list): the frames that follow are drawn. Capture phase, so that no handler can stop it.
    const wake = () => this.wake();
    for (const type of ['pointerdown', 'pointermove', 'pointerup', 'wheel', 'keydown', 'keyup', 'input',
                        'change', 'click', 'resize', 'focus'])
      window.addEventListener(type, wake, { capture: true, passive: true });
    document.addEventListener('visibilitychange', wake);
  }

  ensure() {
    if (this.looping) return;
    this.looping = true;
    this.viewport.setAnimationLoop(this.frame);
  }

  stop() {
    this.viewport.setAnimationLoop(null);
    this.looping = false;
  }

  // Something the picture shows changed: the frames of the next moments are drawn.
  wake() {
    this.redraw.wake(performance.now());
    this.ensure();
  }

  // Whether the frame at `now` is to be drawn (once per frame: redraw.js counts them).
  due(now) {
    return this.redraw.due(now);
  }

  get drawn() {
    return this.redraw.drawn;
  }

  get skipped() {
    return this.redraw.skipped;
  }
}
