// Push: a body grabbed with the pointer (input.js) is pulled at the grabbed point towards the
// pointer's spot on the plane through that point facing the camera, by a force proportional to the
// distance (kPushGain, at most kMaxPush), re-sent each frame with a short ttl (rigid-view's), so
// that it stops when the button is released. A line shows the pull.
import * as THREE from 'three';

const kPushGain = 20;  // N per m of drag
const kMaxPush = 200;  // N

export class Push {
  // scene: where the pull's line is drawn; viewport (viewport.js); connection (connection.js).
  constructor(scene, viewport, connection) {
    this.viewport = viewport;
    this.connection = connection;
    this.grab = null;  // { id, body, local (from the CoM, in B), plane, target (W) }
    this.sent = 0;     // pushes sent (window.rigidView.pushes)
    this.line = new THREE.Line(new THREE.BufferGeometry(), new THREE.LineBasicMaterial({ color: 0xffffff }));
    this.line.visible = false;
    this.line.frustumCulled = false;
    scene.add(this.line);
  }

  get active() {
    return this.grab !== null;
  }

  // Grabs `body` at `point` (W): the point in B, R_WB^T (p_WP - p_WBo), and the drag's plane.
  start(body, point) {
    const local = point.clone().sub(body.p).applyQuaternion(body.q.clone().invert());
    const normal = this.viewport.camera.getWorldDirection(new THREE.Vector3());
    this.grab = { id: body.id, body, local, plane: new THREE.Plane().setFromNormalAndCoplanarPoint(normal, point),
                  target: point.clone() };
  }

  // The pointer's ray moved: the pull's target where it meets the plane.
  drag(ray) {
    ray.intersectPlane(this.grab.plane, this.grab.target);
  }

  release() {
    this.grab = null;
    this.line.visible = false;
  }

  // Once per animation frame while grabbed: the push for this frame, and its line. Returns whether
  // one was sent (the picture changes: the line follows the body).
  send() {
    const grab = this.grab;
    if (!grab || !this.connection.open) return false;
    // The grabbed point in W: p_WBo + R_WB p_BoP.
    const at = grab.local.clone().applyQuaternion(grab.body.q).add(grab.body.p);
    const f = grab.target.clone().sub(at).multiplyScalar(kPushGain);
    if (f.length() > kMaxPush) f.setLength(kMaxPush);
    this.line.geometry.setFromPoints([at, grab.target]);
    this.line.visible = true;
    this.connection.send({ op: 'push', body: grab.id, force: [f.x, f.y, f.z],
                           point: [grab.local.x, grab.local.y, grab.local.z] });
    this.sent += 1;
    return true;
  }
}
