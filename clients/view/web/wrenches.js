// Wrench arrows: one per wrench rigidd accepted that still acts (rigid-view forwards the newest per
// source, body and key, at most kMaxWrenchesShown, 20 times a second; in playback the recorded
// ones acting on the state shown), at its application point, along its force,
// kArrowMetresPerNewton long; and for its torque, a circular arrow about the torque's axis through
// the body's origin (TorqueArcs, below). A force arrow is drawn over everything (a push's point is
// on its body's surface, and its arrow often points into the body) and is never shorter than
// kMinArrowOfDistance times its distance from the camera (a few percent of the view), so that a
// small force, or a far one, stays visible.
import * as THREE from 'three';

import { kMaxWrenchesShown } from './protocol.js';

const kArrowMetresPerNewton = 0.01;
const kMinArrowOfDistance = 0.06;
const isVec3 = (a) => Array.isArray(a) && a.length === 3 && a.every(Number.isFinite);

// rigidd's ticks_to_live (server/common/wrench_table.cpp): the ticks a wrench acts for, ttl / dt
// rounded up (a ratio within 1e-9 of an integer counts as that integer), at least 1.
function ticksToLive(ttl, dt) {
  const ratio = ttl / dt, nearest = Math.round(ratio);
  const ticks = Math.abs(ratio - nearest) <= 1e-9 * Math.max(1, nearest) ? nearest : Math.ceil(ratio);
  return Math.max(1, ticks);
}

export class Wrenches {
  // scene: where the arrows are drawn; bodies (bodies.js): where the wrenches act; camera: how far
  // an arrow is from the eye (its least length).
  constructor(scene, bodies, camera = null) {
    this.scene = scene;
    this.bodies = bodies;
    this.camera = camera;
    this.list = [];       // the last "wrenches" message's, checked
    this.sceneDt = 0;     // s: the scene's step (0: unknown, ttl not applied)
    this.arrows = [];     // ArrowHelpers, reused
    this.torqueArcs = new TorqueArcs(scene);
    this.drawn = [];      // the force arrows drawn now: [{ body, from (W), force (W) }]
    this.twisted = [];    // the torque arrows drawn now (TorqueArcs.draw)
  }

  newScene(msg) {
    this.sceneDt = Number.isFinite(msg.dt) && msg.dt > 0 ? msg.dt : 0;
    this.list = [];
  }

  // A "wrenches" message (protocol.hpp, wrenches_json): whether it changes what may be drawn.
  set(msg) {
    if (!Array.isArray(msg.wrenches)) return false;
    const changed = this.list.length > 0 || msg.wrenches.length > 0;
    this.list = msg.wrenches.slice(-kMaxWrenchesShown).filter((w) => w && Number.isInteger(w.body) &&
      Number.isFinite(w.tick) && Number.isFinite(w.ttl) && isVec3(w.force) && isVec3(w.point) &&
      (w.torque === undefined || isVec3(w.torque)));
    return changed;
  }

  // Accepted at tick k, a wrench acts on the steps k -> k+1 ... k+n-1 -> k+n: it is drawn with the
  // states those steps produced, k < tick <= k + n, and not past `until` (playback: replaced by a
  // newer wrench with its key, or cleared by a reset). Force and torque arrows alike.
  acting(w, tick) {
    if (tick <= w.tick) return false;
    if (Number.isInteger(w.until) && tick > w.until) return false;
    return !(this.sceneDt > 0) || tick <= w.tick + ticksToLive(w.ttl, this.sceneDt);
  }

  // Once per animation frame: the arrows of the wrenches acting on the state shown.
  update() {
    const last = this.bodies.lastState;
    const tick = last ? last.tick : -Infinity;
    const drawn = [];
    const twisted = [];
    const arrows = this.arrows;
    for (const w of this.list) {
      const b = this.bodies.byId.get(w.body);
      if (!b || !b.placed || !this.acting(w, tick)) continue;
      if (w.torque) this.torqueArcs.draw(w, b, twisted);
      // Application point in W: p_WBo + R_WB p_BoP; the force in W (R_WB f_B when given in B).
      const from = new THREE.Vector3(...w.point).applyQuaternion(b.q).add(b.p);
      const f = new THREE.Vector3(...w.force);
      if (w.force_frame === 'body') f.applyQuaternion(b.q);
      const newtons = f.length();
      if (!(newtons > 1e-9)) continue;
      const k = drawn.length;
      if (!arrows[k]) {
        arrows[k] = new THREE.ArrowHelper(new THREE.Vector3(1, 0, 0), new THREE.Vector3(), 1, 0xffd54f);
        for (const part of [arrows[k].line, arrows[k].cone]) {
          part.material.depthTest = false;
          part.renderOrder = 10;
        }
        this.scene.add(arrows[k]);
      }
      const least = Math.max(this.camera ? kMinArrowOfDistance * this.camera.position.distanceTo(from) : 0, 0.05);
      const length = Math.min(Math.max(newtons * kArrowMetresPerNewton, least), Math.max(3, least));
      arrows[k].position.copy(from);
      arrows[k].setDirection(f.clone().divideScalar(newtons));
      arrows[k].setLength(length, Math.min(0.2 * length, 0.15), Math.min(0.1 * length, 0.08));
      arrows[k].visible = true;
      drawn.push({ body: w.body, from: from.toArray(), force: f.toArray(), length });
    }
    for (let k = drawn.length; k < arrows.length; ++k) arrows[k].visible = false;
    this.torqueArcs.hideFrom(twisted.length);
    this.drawn = drawn;
    this.twisted = twisted;
  }
}

// Torque arrows: for a wrench's torque tau (N m; in W, or R_WB tau_B when given in B), an arc of
// 270 degrees in the plane through p_WBo perpendicular to tau, ending in a cone: the arc turns
// about tau by the right-hand rule (counter-clockwise seen from the tip of tau). Its radius is the
// body's (its bounding sphere about Bo) plus a margin, so it stays outside the body; its size
// says nothing of |tau| (a torque has no point to scale from). One unit arc about z (three.js's
// TorusGeometry: from +x counter-clockwise, here to -y, where the cone points along +x, the arc's
// tangent there), posed per torque: z -> the axis, scaled by the radius.
const kTorqueColor = 0x64ffda;  // not the force arrows' amber, nor a body's colour (shapes.js)
const kTorqueArc = 1.5 * Math.PI;

class TorqueArcs {
  constructor(scene) {
    this.scene = scene;
    this.pool = [];
    this.unit = null;
  }

  make() {
    if (!this.unit) {
      const material = new THREE.MeshBasicMaterial({ color: kTorqueColor });
      const cone = new THREE.ConeGeometry(0.09, 0.3, 12);  // along +y, centred
      cone.rotateZ(-Math.PI / 2);                           // along +x
      cone.translate(0.15, -1, 0);                          // its base on the arc's end, (0, -1, 0)
      this.unit = { arc: new THREE.TorusGeometry(1, 0.025, 6, 36, kTorqueArc), cone, material };
    }
    const group = new THREE.Group();
    group.add(new THREE.Mesh(this.unit.arc, this.unit.material));
    group.add(new THREE.Mesh(this.unit.cone, this.unit.material));
    this.scene.add(group);
    return group;
  }

  // Draws w's torque on body b (if not zero) and adds what is drawn to `out`: { body, center
  // (p_WBo), torque (W), axis (unit, W), radius, tip (the cone's base on the arc, W), tipDirection
  // (where the cone points, W) }.
  draw(w, b, out) {
    const tau = new THREE.Vector3(...w.torque);
    if (w.torque_frame === 'body') tau.applyQuaternion(b.q);  // tau_W = R_WB tau_B
    const size = tau.length();
    if (!(size > 1e-12) || out.length >= kMaxWrenchesShown) return;
    const k = out.length;
    const g = this.pool[k] || (this.pool[k] = this.make());
    const axis = tau.clone().divideScalar(size);
    const radius = Math.max(1.3 * b.radius, 0.1);
    g.position.copy(b.p);
    g.quaternion.setFromUnitVectors(new THREE.Vector3(0, 0, 1), axis);
    g.scale.setScalar(radius);
    g.visible = true;
    g.updateMatrix();
    // Where the cone is and where it points, from the pose given to three.js (what is drawn).
    const tip = new THREE.Vector3(0, -1, 0).applyMatrix4(g.matrix);
    const tipDirection = new THREE.Vector3(1, 0, 0).applyQuaternion(g.quaternion);
    out.push({ body: w.body, center: b.p.toArray(), torque: tau.toArray(), axis: axis.toArray(),
               radius, tip: tip.toArray(), tipDirection: tipDirection.toArray() });
  }

  hideFrom(k) {
    for (; k < this.pool.length; ++k) this.pool[k].visible = false;
  }
}
