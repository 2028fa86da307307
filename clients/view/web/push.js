// Push: a body grabbed with the pointer (input.js) follows the pointer's spot T on the plane
// through the grab facing the camera. Its centre of mass is pulled towards T less the grab's
// offset from it (as it was in W when grabbed) by a damped spring scaled by the body's mass m:
// F = m (wn^2 (T - P) - 2 zeta wn v_WBo), P = p_WBo + that offset, F through the centre of mass.
// Critically damped (zeta = 1), the body follows the pointer and settles on it instead of swinging
// about it, so that when the button is released it carries on at about the pointer's speed rather
// than with whatever speed a spring alone had pumped into it. Through the centre of mass the pull
// leaves the body's turning alone: at the grabbed point it also drove a rotation whose mode (a
// sphere's surface point accelerates 3.5 times as fast as its centre under a tangential force)
// was too quick for the loop's delay and swung the body away. The force is bounded by the scene's
// max_force and re-sent each frame with a short ttl (rigid-view's), so that it stops when the
// button is released. A line from P to T shows the pull, drawn over everything.
import * as THREE from 'three';

// rad/s (wn): the pointer is followed within ~1 s. The pull acts on the state the page was last
// sent, so it lags by the loop's delay tau (rigidd -> rigid-view -> page -> rigidd, and a frame of
// the page: ~50-150 ms); with critical damping the loop's crossover is at ~2 wn, where its phase
// margin, ~76 degrees less 2 wn tau, must stay positive: wn = 4 keeps it so for tau up to ~0.16 s.
const kNaturalFrequency = 4;
const kDamping = 1;           // zeta: critical
const kMaxPush = 1e4;         // N: rigid-view's bound on a page's push (protocol.hpp)

export class Push {
  // scene: where the pull's line is drawn; viewport (viewport.js); connection (connection.js).
  constructor(scene, viewport, connection) {
    this.viewport = viewport;
    this.connection = connection;
    // { id, body, offset (p_BoP at the grab, W), plane, target (W), last: { p, simTime, v } }
    this.grab = null;
    this.sent = 0;          // pushes sent (window.rigidView.pushes)
    this.lastForce = null;  // the last push's force (W), for the tests
    this.maxForce = kMaxPush;
    this.line = new THREE.Line(new THREE.BufferGeometry(),
                               new THREE.LineBasicMaterial({ color: 0xffffff, depthTest: false,
                                                             transparent: true }));
    this.line.visible = false;
    this.line.frustumCulled = false;
    this.line.renderOrder = 10;  // over the bodies: the pull shows even inside its body
    scene.add(this.line);
  }

  get active() {
    return this.grab !== null;
  }

  // The scene message's limit on a push (max_force; <= 0 or missing: rigid-view's alone).
  newScene(msg) {
    const f = msg.max_force;
    this.maxForce = Number.isFinite(f) && f > 0 ? Math.min(f, kMaxPush) : kMaxPush;
    this.release();
  }

  // Grabs `body` at `point` (W): the offset p_BoP in W, kept while dragging, and the drag's plane.
  start(body, point) {
    const normal = this.viewport.camera.getWorldDirection(new THREE.Vector3());
    this.grab = { id: body.id, body, offset: point.clone().sub(body.p),
                  plane: new THREE.Plane().setFromNormalAndCoplanarPoint(normal, point),
                  target: point.clone(), last: null };
  }

  // The pointer's ray moved: the pull's target where it meets the plane.
  drag(ray) {
    ray.intersectPlane(this.grab.plane, this.grab.target);
  }

  release() {
    this.grab = null;
    this.line.visible = false;
  }

  // The force (W) for the pulled point `at` (W) moving at `v` (W), bounded by max_force.
  force(at, v) {
    const b = this.grab.body;
    const m = Number.isFinite(b.mass) && b.mass > 0 ? b.mass : 1;
    const wn = kNaturalFrequency;
    const f = this.grab.target.clone().sub(at).multiplyScalar(m * wn * wn)
      .addScaledVector(v, -2 * kDamping * wn * m);
    if (f.length() > this.maxForce) f.setLength(this.maxForce);
    return f;
  }

  // The centre of mass's velocity (W): the body's published one when the page has it (every body
  // of a small scene; a large one's watched body, connection.js), else from its last two
  // positions over their sim time.
  velocity(simTime) {
    const b = this.grab.body;
    if (b.moving) return b.v.clone();
    const last = this.grab.last;
    if (!last || simTime > last.simTime) {
      const v = last ? b.p.clone().sub(last.p).divideScalar(simTime - last.simTime) : new THREE.Vector3();
      this.grab.last = { p: b.p.clone(), simTime, v };
    }
    return this.grab.last.v.clone();
  }

  // Once per animation frame while grabbed: the push for this frame, and its line. `simTime`: the
  // state shown's. Returns whether one was sent (the picture changes: the line follows the body).
  send(simTime) {
    const grab = this.grab;
    if (!grab || !this.connection.open) return false;
    const at = grab.body.p.clone().add(grab.offset);
    const f = this.force(at, this.velocity(simTime));
    this.line.geometry.setFromPoints([at, grab.target]);
    this.line.visible = true;
    this.connection.send({ op: 'push', body: grab.id, force: [f.x, f.y, f.z], point: [0, 0, 0] });
    this.lastForce = f.toArray();
    this.sent += 1;
    return true;
  }
}
