// The page's decoder of state frames (clients/view/web/protocol.js, with the constants the build
// generates from protocol.hpp) on frames that rigid-view's own encoder made (view_write_frames):
// every field of a whole frame in f64 and in f32, of a pose frame with watched bodies and of one
// with no drift decoded to the state the encoder was given; frames cut short, with a wrong magic
// or of a wrong length refused; the limits the page shares with rigid-view equal protocol.hpp's.
// usage: node protocol_test.mjs WRITE_FRAMES WEB_DIR (WEB_DIR: the page as built, next to
// rigid-view)
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';

import { test, done } from './unit.mjs';

const [writeFrames, webDir] = process.argv.slice(2);
const protocol = await import(pathToFileURL(join(webDir, 'protocol.js')).href);
const { limits, cases } = JSON.parse(execFileSync(writeFrames, { encoding: 'utf8' }));

const bufferOf = (c) => {
  const bytes = Buffer.from(c.frame, 'base64');
  return bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
};
const f32 = (xs) => xs.map(Math.fround);
const same = (actual, expected, what) => assert.deepEqual(Array.from(actual), expected, what);

// The header and the per-body arrays every frame has.
function checkCommon(s, c, float32) {
  const n = c.ids.length;
  assert.equal(s.n, n);
  assert.equal(s.generation, c.generation);
  assert.equal(s.tick, c.tick);
  assert.equal(s.simTime, c.sim_time);
  assert.equal(s.stampNs, BigInt(c.stamp_ns));
  same(s.ids, c.ids, 'ids');
  assert.equal(s.position instanceof Float32Array, float32);
  same(s.position, float32 ? f32(c.position) : c.position, 'position');
  same(s.orientation, float32 ? f32(c.orientation) : c.orientation, 'orientation');
}

for (const c of cases.filter((x) => x.name.startsWith('whole'))) {
  test(`a ${c.name} frame decodes to the state encoded`, () => {
    const s = protocol.decodeState(bufferOf(c));
    const float32 = c.name.endsWith('f32');
    assert.equal(s.poses, false);
    checkCommon(s, c, float32);
    same(s.linearVelocity, float32 ? f32(c.linear_velocity) : c.linear_velocity, 'linear velocity');
    same(s.angularVelocity, float32 ? f32(c.angular_velocity) : c.angular_velocity, 'angular velocity');
    same(s.energyDrift, c.energy_drift, 'energy drift');
    same(s.momentumDrift, c.momentum_drift, 'momentum drift');
    assert.equal(s.worst, null);
    assert.equal(s.watched, null);
  });
}

// The largest drift above 0 and its slot (-1 when none), as protocol.hpp says a pose frame has it.
function worstOf(drift) {
  let value = 0, slot = -1;
  drift.forEach((d, i) => { if (d > value) { value = d; slot = i; } });
  return [value, slot];
}

for (const c of cases.filter((x) => x.name.startsWith('pose'))) {
  test(`a ${c.name} frame decodes to the state encoded`, () => {
    const s = protocol.decodeState(bufferOf(c));
    assert.equal(s.poses, true);
    checkCommon(s, c, true);
    assert.equal(s.linearVelocity, null);
    assert.equal(s.energyDrift, null);
    const [energy, energySlot] = worstOf(c.energy_drift), [momentum, momentumSlot] = worstOf(c.momentum_drift);
    assert.deepEqual(s.worst, { energy, energySlot, momentum, momentumSlot });
    if (c.name === 'pose, no drift') assert.equal(s.worst.energySlot, -1);
    // Each watched body the state holds, in the order asked, with its whole published state.
    const expected = c.watched.map((id) => c.ids.indexOf(id)).filter((slot) => slot >= 0).map((slot) => ({
      slot, energy: c.energy_drift[slot], momentum: c.momentum_drift[slot],
      state: [...c.position.slice(3 * slot, 3 * slot + 3), ...c.orientation.slice(4 * slot, 4 * slot + 4),
              ...c.linear_velocity.slice(3 * slot, 3 * slot + 3), ...c.angular_velocity.slice(3 * slot, 3 * slot + 3)],
    }));
    assert.equal(s.watched.length, expected.length);
    if (c.name === 'pose, watched') assert.equal(expected.length, 2);
    s.watched.forEach((r, k) => {
      assert.deepEqual({ slot: r.slot, energy: r.energy, momentum: r.momentum, state: Array.from(r.state) },
                       expected[k], `watched record ${k}`);
    });
  });
}

test('frames cut short, of another magic or of a wrong length are refused', () => {
  const whole = bufferOf(cases.find((x) => x.name === 'whole f64'));
  const pose = bufferOf(cases.find((x) => x.name === 'pose, watched'));
  assert.throws(() => protocol.decodeState(whole.slice(0, protocol.kStateHeaderBytes - 1)), /short state frame/);
  const other = whole.slice(0);
  new DataView(other).setUint32(0, protocol.kStateMagic + 1, true);
  assert.throws(() => protocol.decodeState(other), /bad state frame/);
  assert.throws(() => protocol.decodeState(whole.slice(0, whole.byteLength - 4)), /state frame of the wrong length/);
  const longer = new Uint8Array(whole.byteLength + 8);
  longer.set(new Uint8Array(whole));
  assert.throws(() => protocol.decodeState(longer.buffer), /state frame of the wrong length/);
  assert.throws(() => protocol.decodeState(pose.slice(0, pose.byteLength - 8)), /pose frame of the wrong length/);
  assert.throws(() => protocol.decodeState(pose.slice(0, protocol.kStateHeaderBytes + 8)), /pose frame of the wrong length/);
});

test('the limits the page uses are protocol.hpp\'s', () => {
  for (const [name, value] of Object.entries(limits)) assert.equal(protocol[name], value, name);
});

done();
