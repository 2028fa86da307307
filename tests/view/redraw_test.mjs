// The page's draw-on-change decision (clients/view/web/redraw.js), on simulated 60 Hz animation
// frames: which frames are drawn after a change, while changes go on, and when nothing changes.
// usage: node redraw_test.mjs
import assert from 'node:assert/strict';
import { Redraw } from '../../clients/view/web/redraw.js';
import { test, done } from './unit.mjs';

const kRefreshMs = 1000 / 60;

// Frames from `start` for `seconds`; wakeAt(t) says whether something changed just before the
// frame at t. Returns the times of the frames drawn.
function run(r, seconds, { start = 0, wakeAt = () => false } = {}) {
  const drawn = [];
  for (let k = 0; k * kRefreshMs < seconds * 1000; ++k) {
    const t = start + k * kRefreshMs;
    if (wakeAt(t)) r.wake(t);
    if (r.due(t)) drawn.push(t);
  }
  return drawn;
}

test('the first frame is drawn, then only a frame a heartbeat while nothing changes', () => {
  const r = new Redraw({ linger: 250, heartbeat: 1000 });
  const drawn = run(r, 10);
  assert.equal(drawn[0], 0);
  // About one a second: at 0, then the first frame at least 1000 ms after the last drawn (the
  // frame times are sums of 1000 / 60, not exact: 1000 ms may fall a rounding before a frame).
  assert.ok(drawn.length >= 9 && drawn.length <= 10, `drawn at ${drawn.map((t) => t.toFixed(0))}`);
  for (let i = 1; i < drawn.length; ++i) {
    const gap = drawn[i] - drawn[i - 1];
    assert.ok(gap >= 1000 - 1e-6 && gap < 1000 + kRefreshMs + 1e-6, `gap ${gap} ms`);
  }
  assert.equal(r.drawn, drawn.length);
  assert.equal(r.skipped, 600 - drawn.length);
});

// (Lingers of 240 ms, between refreshes, so that the frames drawn do not depend on rounding.)
test('a change draws every frame for the linger, then the page idles again', () => {
  const r = new Redraw({ linger: 240, heartbeat: 1000 });
  run(r, 2);  // idle
  const at = 2000 + 10 * kRefreshMs;
  const drawn = run(r, 2, { start: 2000, wakeAt: (t) => Math.abs(t - at) < 1e-6 });
  // Every frame from the change to 240 ms after it (15 frames: at + 0 .. at + 14 refreshes).
  const after = drawn.filter((t) => t >= at - 1e-6 && t <= at + 240);
  assert.equal(after.length, 15, `drawn at ${drawn.map((t) => (t - at).toFixed(0))}`);
  // After the linger nothing until a heartbeat after the last frame drawn.
  const later = drawn.filter((t) => t > at + 240);
  for (const t of later) assert.ok(t - (at + 14 * kRefreshMs) >= 1000 - 1e-6, `drawn ${t - at} ms after the change`);
  assert.ok(later.length <= 1, `${later.length} frames drawn after the linger`);
});

test('changes at every state (a moving scene, 30 states a second) draw every frame', () => {
  const r = new Redraw();
  const drawn = run(r, 10, { wakeAt: (t) => Math.round(t / kRefreshMs) % 2 === 0 });
  assert.equal(drawn.length, 600);
  assert.equal(r.skipped, 0);
});

test('states a few times a second draw each for the linger and skip the rest', () => {
  // A scene published at 2 Hz: each state wakes the page for 240 ms of its 500.
  const r = new Redraw({ linger: 240, heartbeat: 1000 });
  const drawn = run(r, 10, { wakeAt: (t) => Math.round(t / kRefreshMs) % 30 === 0 });
  assert.equal(drawn.length, 20 * 15, `${drawn.length} frames drawn`);
  assert.equal(r.skipped, 600 - 20 * 15);
});

test('a wake later than the frame it precedes still draws that frame and the linger after it', () => {
  // (A state applied inside a frame wakes with performance.now(), a little after the frame's
  // timestamp.)
  const r = new Redraw({ linger: 250, heartbeat: 1000 });
  run(r, 1.5);
  r.wake(1600 + 3);
  assert.equal(r.due(1600), true);
  assert.equal(r.due(1600 + 250), true);
  assert.equal(r.due(1600 + 260), false);
});

test('a linger of 0 draws the frame of the change only', () => {
  const r = new Redraw({ linger: 0, heartbeat: 1000 });
  run(r, 1.5);
  r.wake(1600);
  assert.equal(r.due(1600), true);
  assert.equal(r.due(1600 + kRefreshMs), false);
});

test('bad options are refused by name', () => {
  assert.throws(() => new Redraw({ linger: -1 }), /linger/);
  assert.throws(() => new Redraw({ linger: NaN }), /linger/);
  assert.throws(() => new Redraw({ heartbeat: 0 }), /heartbeat/);
  assert.throws(() => new Redraw({ heartbeat: Infinity }), /heartbeat/);
});

done();
