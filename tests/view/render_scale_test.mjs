// The page's dynamic resolution (clients/view/web/render_scale.js), driven by simulated
// animation frames: a page whose frame rate depends on its render scale the way a software
// renderer's does (frames cost per pixel), and the decisions the controller takes on it.
// usage: node render_scale_test.mjs
import assert from 'node:assert/strict';
import { RenderScale } from '../../clients/view/web/render_scale.js';
import { test, done } from './unit.mjs';

const kRefreshMs = 1000 / 60;

// Runs `seconds` of animation frames on a 60 Hz display: a frame takes frameMs(scale, t) and is
// shown at the first refresh after it is done (so a page slower than the refresh draws every
// second or third one). Returns the time (ms) at the end and calls onFrame(scale, t) per frame.
function run(control, seconds, frameMs, { start = 0, visible = () => true, onFrame = () => {} } = {}) {
  let t = start;
  const end = start + seconds * 1000;
  while (t < end) {
    const scale = control.frame(t, visible(t));
    onFrame(scale, t);
    t += Math.ceil(frameMs(scale, t) / kRefreshMs - 1e-9) * kRefreshMs;
  }
  return t;
}

test('a page that keeps up stays at full resolution', () => {
  const c = new RenderScale();
  run(c, 120, () => 10);
  assert.equal(c.scale, 1);
  assert.equal(c.lowered, 0);
  assert.equal(c.raised, 0);
});

test('a slow page is lowered one step every two seconds, down to the minimum and no lower', () => {
  const c = new RenderScale({ min: 0.25, step: 0.75, lowerAfter: 2 });
  const seen = [];
  const t = run(c, 2.5, () => 25);
  assert.equal(c.scale, 0.75, 'lowered after two slow seconds');
  run(c, 15, () => 25, { start: t, onFrame: (s) => { if (seen.at(-1) !== s) seen.push(s); } });
  // 1, 0.75, 0.5625, 0.421875, 0.31640625, then 0.25 (the minimum, not 0.2373046875).
  assert.deepEqual(seen, [0.75, 0.5625, 0.421875, 0.31640625, 0.25]);
  assert.equal(c.lowered, 5);
});

test('a page far too slow goes down by what it needs, not a step at a time', () => {
  // 10^4 bodies in software rendering: ~5 frames/s at full resolution, the cost per pixel.
  const c = new RenderScale({ min: 0.25, lowerAfter: 2 });
  let t = run(c, 2.5, (s) => 200 * s * s);
  assert.ok(c.scale > 0.28 && c.scale < 0.31, `one decision: sqrt(17.1 / 191.5) = 0.30, got ${c.scale}`);
  t = run(c, 2.5, (s) => 200 * s * s, { start: t });
  assert.equal(c.scale, 0.25);
  assert.equal(c.lowered, 2);
});

test('stalls of the machine, one slow second at a time, do not lower the scale', () => {
  // A 100 ms stall (six refreshes) every 5 s, for ten minutes.
  const c = new RenderScale();
  run(c, 600, (s, t) => (t % 5000 < kRefreshMs ? 100 : 10));
  assert.equal(c.scale, 1);
  assert.equal(c.lowered, 0);
});

test('a refresh or two missed every second do not lower; three do', () => {
  // A frame that takes two refreshes every `every` refreshes.
  const missing = (every) => (s, t) => (Math.round(t / kRefreshMs) % every === 0 ? 20 : 10);
  for (const every of [60, 30]) {  // 59, 58 frames a second
    const c = new RenderScale();
    run(c, 60, missing(every));
    assert.equal(c.scale, 1, `every ${every} refreshes`);
  }
  const c = new RenderScale();
  run(c, 5, missing(20));  // 57 frames a second
  assert.ok(c.scale < 1, `57 frames a second should lower the scale, at ${c.scale}`);
});

// A software renderer's page: it keeps up at 0.5625 and below, and misses refreshes above.
const perPixel = (scale) => (scale <= 0.6 ? 14 : 19);

test('a page at its limit settles on the scale it can draw, its probes backing off', () => {
  const c = new RenderScale({ raiseAfter: 10, maxRaiseAfter: 320, probeWindow: 30 });
  let atLimit = 0, frames = 0, lowest = 1;
  run(c, 900, perPixel, {
    onFrame: (s, t) => {
      if (t < 5000) return;  // the descent
      lowest = Math.min(lowest, s);
      if (t >= 300000) {
        ++frames;
        if (s === 0.5625) ++atLimit;
      }
    },
  });
  assert.equal(lowest, 0.5625, 'never below the scale it can draw');
  assert.ok(c.failedProbes >= 4, `probes failed: ${c.failedProbes}`);
  assert.ok(c.raiseAfter >= 160, `wait before a probe: ${c.raiseAfter} s`);
  assert.ok(atLimit / frames > 0.97, `share of frames at 0.5625 after 300 s: ${atLimit / frames}`);
});

test('a page that becomes fast again is raised back to full resolution', () => {
  const c = new RenderScale({ raiseAfter: 10 });
  const t = run(c, 5, () => 25);
  assert.ok(c.scale < 1);
  run(c, 100, () => 10, { start: t });
  assert.equal(c.scale, 1);
  assert.equal(c.failedProbes, 0);
});

test('a hidden page is not judged by the frames it does not get', () => {
  const c = new RenderScale();
  // Hidden for 60 s: a browser gives a background page a frame a second, or none.
  run(c, 60, () => 1000, { visible: () => false });
  assert.equal(c.scale, 1);
  assert.equal(c.lowered, 0);
});

test('reset returns to full resolution and the first wait', () => {
  const c = new RenderScale({ raiseAfter: 10 });
  run(c, 900, perPixel);
  assert.ok(c.scale < 1 && c.raiseAfter > 10);
  c.reset();
  assert.equal(c.scale, 1);
  assert.equal(c.raiseAfter, 10);
  assert.equal(c.frame(1e6), 1);  // a new window: no decision on the first frame
});

test('bad options are refused with the option named', () => {
  assert.throws(() => new RenderScale({ min: 0 }), /min must be in \(0, 1\], got 0/);
  assert.throws(() => new RenderScale({ step: 1 }), /step must be in \(0, 1\), got 1/);
  assert.throws(() => new RenderScale({ slowFps: 60, fastFps: 50 }), /slowFps <= fastFps/);
  assert.throws(() => new RenderScale({ lowerAfter: 0.5 }), /lowerAfter must be an integer >= 1, got 0.5/);
  assert.throws(() => new RenderScale({ raiseAfter: 0 }), /raiseAfter <= maxRaiseAfter/);
  assert.throws(() => new RenderScale({ raiseAfter: 20, maxRaiseAfter: 10 }), /raiseAfter <= maxRaiseAfter/);
  assert.throws(() => new RenderScale({ probeWindow: NaN }), /probeWindow must be >= 0, got NaN/);
});

done();
