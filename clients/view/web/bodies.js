// The scene's bodies as the page holds and draws them: built from the scene message, placed by
// each state frame (protocol.js). Bodies are drawn with one mesh per shape group (shapes.js,
// groupsOf): a scene of 10^4 spheres of any sizes is one draw call. Small scenes: a
// THREE.InstancedMesh, each body an instance whose matrix is its pose from the state frame times
// its shape's scale and frame in B. Scenes of more than kManyBodies bodies: ImpostorBodies
// (impostors.js), every body one quad, posed and ray-cast on the GPU.
import * as THREE from 'three';

import { ImpostorBodies, impostorKind, impostorShape } from './impostors.js';
import { colorOf, geometryOf, groupsOf, kManyBodies, lookOf, shapeMatrix } from './shapes.js';
import { addMarkings } from './stage.js';

const kHidden = new THREE.Matrix4().makeScale(0, 0, 0);  // an instance not yet placed by a state
const scratch = { m: new THREE.Matrix4(), one: new THREE.Vector3(1, 1, 1), c: new THREE.Color() };

// Whether a scene is drawn as a large one (impostors, no multisampling).
export const isLarge = (msg) => msg.bodies.length > kManyBodies;

export class Bodies {
  constructor(scene) {
    this.group = new THREE.Group();
    scene.add(this.group);
    // id -> { id, name, shape, index (scene order), group, instance (small scenes), mass, inertia,
    //        radius, shape4 (the unit geometry's scale and frame in B), unit (large scenes: the
    //        unit shape picked against), p (p_WBo), q (q_WB), v (v_WBo in W), w (w_WB in W),
    //        placed, moving (v and w are the published ones) }
    this.byId = new Map();
    this.list = [];            // in scene order
    this.instanced = [];       // small scenes: { mesh, ids: Int32Array (instance -> body id) }
    this.impostors = null;     // large scenes: ImpostorBodies
    this.slots = new Int32Array(0);  // the last state's slot -> scene index (-1: not in the scene)
    this.seen = null;          // the last state's poses (posesChanged)
    this.lastState = null;     // { tick, simTime, bodies, generation } of the last state applied
    this.statesApplied = 0;
  }

  // Before a new scene: the old one's meshes freed.
  clear() {
    for (const g of this.instanced) {
      this.group.remove(g.mesh);
      g.mesh.geometry.dispose();
      g.mesh.material.dispose();
      g.mesh.dispose();
    }
    this.instanced.length = 0;
    if (this.impostors) this.impostors.dispose();
    this.impostors = null;
    this.byId.clear();
  }

  // The scene message's bodies (protocol.hpp, scene_json), none placed until a state comes.
  build(msg) {
    if (isLarge(msg)) this.buildImpostors(msg);
    else this.buildInstanced(msg);
    this.seen = null;
    this.list = msg.bodies.map((d) => this.byId.get(d.id)).filter((b) => b);
  }

  buildInstanced(msg) {
    for (const { b, members } of groupsOf(msg).values()) {
      const material = addMarkings(
        new THREE.MeshStandardMaterial({ roughness: 0.6, metalness: 0.1, ...lookOf(b) }));
      const geometry = geometryOf(b, 1);
      geometry.computeBoundingSphere();
      const mesh = new THREE.InstancedMesh(geometry, material, members.length);
      mesh.instanceMatrix.setUsage(THREE.DynamicDrawUsage);
      // Bodies move every frame: the instances' bounding sphere would be stale for culling, and is
      // recomputed only when picking needs it.
      mesh.frustumCulled = false;
      const ids = new Int32Array(members.length);
      const g = { mesh, ids };
      members.forEach((i, instance) => {
        const d = msg.bodies[i];
        ids[instance] = d.id;
        const shape = shapeMatrix(d);
        const radius = geometry.boundingSphere.radius * shape.getMaxScaleOnAxis();
        mesh.setMatrixAt(instance, kHidden);
        mesh.setColorAt(instance, scratch.c.setHex(colorOf(i)));
        this.byId.set(d.id, body(d, i, { group: g, instance, radius, shape4: shape, unit: undefined }));
      });
      mesh.instanceColor.needsUpdate = true;
      this.group.add(mesh);
      this.instanced.push(g);
    }
  }

  // One draw of impostors per group, posed on the GPU; the scene index is the body's slot in the
  // pose texture. Picking (picking.js) uses each body's unit shape, from the unit geometry's
  // bounds (built for that only, never drawn).
  buildImpostors(msg) {
    this.impostors = new ImpostorBodies(msg.bodies.length);
    for (const { b, members } of groupsOf(msg).values()) {
      const kind = impostorKind(b);
      const geometry = geometryOf(b, members.length);
      geometry.computeBoundingSphere();
      geometry.computeBoundingBox();
      const unit = { round: kind === 'ELLIPSOID', box: geometry.boundingBox };
      const drawn = members.map((i) => {
        const d = msg.bodies[i];
        const shape = shapeMatrix(d);
        this.byId.set(d.id, body(d, i, { group: null, instance: -1, shape4: shape, unit,
                                         radius: geometry.boundingSphere.radius * shape.getMaxScaleOnAxis() }));
        return { slot: i, color: new THREE.Color().setHex(colorOf(i)), ...impostorShape(kind, d, shape) };
      });
      this.group.add(this.impostors.add(kind, drawn, lookOf(b)));
      geometry.dispose();
    }
  }

  find(name) {
    return this.list.find((x) => x.name === name);
  }

  // A decoded state frame (protocol.js): each body at its pose, with its velocities when the frame
  // has them; a pose frame's watched bodies then get their whole published state. Returns whether
  // the poses differ from the last state's (something to draw).
  apply(state) {
    const { n, ids, position: pos, orientation: ori, linearVelocity: vel, angularVelocity: omega } = state;
    const { m, one } = scratch;
    if (this.slots.length !== n) this.slots = new Int32Array(n);
    const slots = this.slots;
    const changed = this.posesChanged(n, ids, pos, ori);
    for (let i = 0; i < n; ++i) {
      const b = this.byId.get(ids[i]);
      slots[i] = b ? b.index : -1;
      if (!b) continue;
      b.p.set(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]);
      b.q.set(ori[4 * i + 1], ori[4 * i + 2], ori[4 * i + 3], ori[4 * i]);
      if (vel) {
        b.v.set(vel[3 * i], vel[3 * i + 1], vel[3 * i + 2]);
        b.w.set(omega[3 * i], omega[3 * i + 1], omega[3 * i + 2]);
      }
      b.placed = true;
      b.moving = !!vel;
      // Large scenes: the pose into the vertex shader's texture; small: the instance's matrix, X_WB
      // (pose) times the shape's scale and frame in B.
      if (this.impostors) this.impostors.setPose(b.index, b.p, b.q);
      else b.group.mesh.setMatrixAt(b.instance, m.compose(b.p, b.q, one).multiply(b.shape4));
    }
    if (state.watched) {
      for (const r of state.watched) {
        const b = r.slot >= 0 && r.slot < n ? this.byId.get(ids[r.slot]) : null;
        if (!b) continue;
        const x = r.state;
        b.p.set(x[0], x[1], x[2]);
        b.q.set(x[4], x[5], x[6], x[3]);
        b.v.set(x[7], x[8], x[9]);
        b.w.set(x[10], x[11], x[12]);
        b.moving = true;
      }
    }
    return changed;
  }

  // Whether a state's poses (ids, positions, orientations) differ from the last state's, which it
  // replaces as the one compared against: kept as views of its buffer (each state comes in a
  // buffer of its own that nothing changes, worker_socket.js), so a moving scene costs a
  // comparison or two and no copy. Exact: a paused scene's states repeat the same numbers. (The
  // watched bodies' double-precision records change nothing drawn.)
  posesChanged(n, ids, pos, ori) {
    const last = this.seen;
    this.seen = { ids, pos, ori };
    if (!last || last.ids.length !== n) return true;
    for (let i = 0; i < 4 * n; ++i) if (last.ori[i] !== ori[i]) return true;
    for (let i = 0; i < 3 * n; ++i) if (last.pos[i] !== pos[i]) return true;
    for (let i = 0; i < n; ++i) if (last.ids[i] !== ids[i]) return true;
    return false;
  }

  // After a state is applied: the poses go to the GPU with the next frame.
  commit(state) {
    if (this.impostors) this.impostors.commit();
    for (const g of this.instanced) {
      g.mesh.instanceMatrix.needsUpdate = true;
      g.mesh.boundingSphere = null;  // stale: recomputed by the next ray cast
    }
    this.statesApplied += 1;
    this.lastState = { tick: state.tick, simTime: state.simTime, bodies: state.n, generation: state.generation };
  }

  // The tick of the state shown, or -1 before the first.
  get tick() {
    return this.lastState ? this.lastState.tick : -1;
  }

  // The pose drawn for a body: position and orientation (w, x, y, z), and the tick it came from.
  // (Small scenes: the pose handed to three.js, in double precision; the GPU gets it as float32.
  // Large scenes: the float32 pose in the texture the impostors' vertex shader reads.)
  renderedPose(name) {
    for (const b of this.byId.values()) {
      if (b.name !== name || !b.placed) continue;
      if (this.impostors) {
        const drawn = this.impostors.pose(b.index);
        return drawn && { tick: this.tick, ...drawn };
      }
      const p = b.p, q = b.q;
      return { tick: this.tick, position: [p.x, p.y, p.z], orientation: [q.w, q.x, q.y, q.z] };
    }
    return null;
  }

  // A body's last published state as the page holds it (velocities in W; null in a large live
  // scene unless the body is selected: pose frames carry the watched bodies' only).
  stateOf(name) {
    for (const b of this.byId.values()) {
      if (b.name !== name || !b.placed) continue;
      return { id: b.id, tick: this.tick,
               position: b.p.toArray(), orientation: [b.q.w, b.q.x, b.q.y, b.q.z],
               linear_velocity: b.moving ? b.v.toArray() : null,
               angular_velocity: b.moving ? b.w.toArray() : null };
    }
    return null;
  }

  // How many bodies the meshes draw, how many meshes (draw calls) that takes, and how: 'instanced'
  // (small scenes) or 'impostors'.
  instances() {
    if (this.impostors) return { meshes: this.impostors.meshes.length, count: this.impostors.count, path: 'impostors' };
    let count = 0;
    for (const g of this.instanced) count += g.mesh.count;
    return { meshes: this.instanced.length, count, path: 'instanced' };
  }
}

// A body of the scene message `d`, at scene index i, drawn as `drawn` says.
function body(d, i, { group, instance, radius, shape4, unit }) {
  return { id: d.id, name: d.name, shape: d.shape, index: i, group, instance, mass: d.mass,
           inertia: d.inertia || null, radius, shape4, unit, p: new THREE.Vector3(),
           q: new THREE.Quaternion(), v: new THREE.Vector3(), w: new THREE.Vector3(), placed: false,
           moving: false };
}
