// Zoom to fit: the camera aimed at the centre of the bodies' bounds, far enough back that a sphere
// around all of them (each body's bounding radius included) fills the view, looking from where it
// looks now (or, before anything was shown, from the default side). A new scene is framed once
// its first state has placed its bodies; "fit" (or the key F) frames it again.
import * as THREE from 'three';

const kMargin = 1.15;     // the sphere's radius times this fills the narrower field of view
const kMinRadius = 0.25;  // m: a single small body is not filled to the edges

// The sphere around the placed bodies: { center, radius }, or null when none is placed.
export function boundsOf(bodies) {
  const box = new THREE.Box3();
  let any = false;
  for (const b of bodies.list) {
    if (!b.placed) continue;
    box.expandByPoint(b.p);
    any = true;
  }
  if (!any) return null;
  const center = box.getCenter(new THREE.Vector3());
  let radius = 0;
  for (const b of bodies.list) {
    if (b.placed) radius = Math.max(radius, b.p.distanceTo(center) + b.radius);
  }
  return { center, radius: Math.max(radius, kMinRadius) };
}

export class Framing {
  // viewport (viewport.js), bodies (bodies.js).
  constructor(viewport, bodies) {
    this.viewport = viewport;
    this.bodies = bodies;
    this.pending = true;  // frame the scene at its first placed state
  }

  newScene() {
    this.pending = true;
  }

  // After a state is applied: the first one of a scene frames it. Whether the camera moved.
  stateApplied() {
    if (!this.pending) return false;
    return this.fit();
  }

  // Frames the placed bodies; whether the camera moved (false: nothing placed yet).
  fit() {
    const bounds = boundsOf(this.bodies);
    if (!bounds) return false;
    this.pending = false;
    const { camera, controls } = this.viewport;
    const half = THREE.MathUtils.degToRad(camera.fov / 2);
    const narrower = camera.aspect >= 1 ? half : Math.atan(Math.tan(half) * camera.aspect);
    const distance = (kMargin * bounds.radius) / Math.sin(narrower);
    const from = camera.position.clone().sub(controls.target);
    if (from.lengthSq() === 0) from.set(3.5, -4.5, 3);
    from.setLength(distance);
    controls.target.copy(bounds.center);
    camera.position.copy(bounds.center).add(from);
    // The near and far planes follow the scene's size (a 100 m scene would be cut at 1000 m).
    camera.near = Math.max(distance / 1000, 1e-3);
    camera.far = Math.max(distance * 100, 1000);
    camera.updateProjectionMatrix();
    controls.update();
    return true;
  }
}
