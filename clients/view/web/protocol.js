// The binary state frames rigid-view sends (clients/view/protocol.hpp says what each field is),
// read as typed arrays over the frame's own buffer: no copy. The offsets and flags come from
// protocol_constants.js, which the build generates from protocol.hpp, so that this decoder and
// rigid-view's encoder share one definition (tests/view/protocol_test.mjs decodes frames that
// rigid-view's encoder made).
import {
  kStateMagic, kStateHeaderBytes, kStateBodiesAt, kStateGenerationAt, kStateFlagsAt, kStateTickAt,
  kStateSimTimeAt, kStateStampAt, kStateFloat32, kStatePoses, kPoseBytesPerBody, kPoseTrailerBytes,
  kPoseWorstEnergyAt, kPoseWorstEnergySlotAt, kPoseWorstMomentumAt, kPoseWorstMomentumSlotAt,
  kPoseWatchedCountAt, kWatchedRecordBytes, kWatchedEnergyAt, kWatchedMomentumAt, kWatchedStateAt,
} from './protocol_constants.js';

export * from './protocol_constants.js';

// A state frame (ArrayBuffer), or throws on one of the wrong size or kind. Returns
// { poses, n, generation, tick, simTime, stampNs (BigInt: rigidd's wall clock at publish, ns),
//   ids (Int32Array, by state slot), position (3n), orientation (4n: w, x, y, z), and
//   whole frames: linearVelocity, angularVelocity (3n each, in W), energyDrift, momentumDrift
//   (Float32Array, n); pose frames: null there, and worst ({ energy, energySlot, momentum,
//   momentumSlot }: slot -1 when every drift is 0) and watched ([{ slot, energy, momentum,
//   state (Float64Array: position 3, orientation 4, linear and angular velocity 3 each) }]) }.
// The per-body reals are Float64Array, or Float32Array for large recordings and pose frames.
export function decodeState(buffer) {
  if (buffer.byteLength < kStateHeaderBytes) throw new Error('short state frame');
  const v = new DataView(buffer);
  if (v.getUint32(0, true) !== kStateMagic) throw new Error('bad state frame');
  const flags = v.getUint32(kStateFlagsAt, true);
  // (Built whole, then filled in: an object spread here cost microseconds a frame in V8.)
  const state = {
    poses: (flags & kStatePoses) !== 0, n: v.getUint32(kStateBodiesAt, true),
    generation: v.getUint32(kStateGenerationAt, true), tick: Number(v.getBigInt64(kStateTickAt, true)),
    simTime: v.getFloat64(kStateSimTimeAt, true), stampNs: v.getBigInt64(kStateStampAt, true),
    ids: null, position: null, orientation: null, linearVelocity: null, angularVelocity: null,
    energyDrift: null, momentumDrift: null, worst: null, watched: null,
  };
  if (state.poses) decodePoses(buffer, v, state);
  else decodeWhole(buffer, state, (flags & kStateFloat32) !== 0);
  return state;
}

function decodeWhole(buffer, state, f32) {
  const n = state.n;
  const real = f32 ? 4 : 8, Real = f32 ? Float32Array : Float64Array;
  if (buffer.byteLength !== kStateHeaderBytes + (13 * real + 12) * n) throw new Error('state frame of the wrong length');
  state.position = new Real(buffer, kStateHeaderBytes, 3 * n);
  state.orientation = new Real(buffer, kStateHeaderBytes + 3 * real * n, 4 * n);
  state.linearVelocity = new Real(buffer, kStateHeaderBytes + 7 * real * n, 3 * n);
  state.angularVelocity = new Real(buffer, kStateHeaderBytes + 10 * real * n, 3 * n);
  state.energyDrift = new Float32Array(buffer, kStateHeaderBytes + 13 * real * n, n);
  state.momentumDrift = new Float32Array(buffer, kStateHeaderBytes + (13 * real + 4) * n, n);
  state.ids = new Int32Array(buffer, kStateHeaderBytes + (13 * real + 8) * n, n);
}

function decodePoses(buffer, v, state) {
  const n = state.n;
  const trailer = kStateHeaderBytes + kPoseBytesPerBody * n;
  const bytes = trailer + kPoseTrailerBytes;
  if (buffer.byteLength < bytes) throw new Error('pose frame of the wrong length');
  const k = v.getUint32(trailer + kPoseWatchedCountAt, true);
  if (buffer.byteLength !== bytes + kWatchedRecordBytes * k) throw new Error('pose frame of the wrong length');
  state.position = new Float32Array(buffer, kStateHeaderBytes, 3 * n);
  state.orientation = new Float32Array(buffer, kStateHeaderBytes + 12 * n, 4 * n);
  state.ids = new Int32Array(buffer, kStateHeaderBytes + 28 * n, n);
  state.worst = { energy: v.getFloat32(trailer + kPoseWorstEnergyAt, true),
                  energySlot: v.getInt32(trailer + kPoseWorstEnergySlotAt, true),
                  momentum: v.getFloat32(trailer + kPoseWorstMomentumAt, true),
                  momentumSlot: v.getInt32(trailer + kPoseWorstMomentumSlotAt, true) };
  state.watched = [];
  for (let r = 0; r < k; ++r) {
    const o = bytes + kWatchedRecordBytes * r;
    state.watched.push({ slot: v.getInt32(o, true), energy: v.getFloat32(o + kWatchedEnergyAt, true),
                         momentum: v.getFloat32(o + kWatchedMomentumAt, true),
                         state: new Float64Array(buffer, o + kWatchedStateAt, 13) });
  }
}
