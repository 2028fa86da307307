// Which body is under a ray (the pointer's): in small scenes three.js's ray cast of the instanced
// meshes; in large scenes, drawn as impostors (no meshes to ray-cast), pickBodies from the poses
// the page holds, the same numbers the impostors are drawn from.
import * as THREE from 'three';

const scratch = {
  X: new THREE.Matrix4(), Xinv: new THREE.Matrix4(), ray: new THREE.Ray(), hit: new THREE.Vector3(),
  sphere: new THREE.Sphere(new THREE.Vector3(), 1), one: new THREE.Vector3(1, 1, 1),
};

// The body the ray hits first. Each body is first tested against its bounding sphere in W (cheap,
// rejects nearly all of them), then exactly against its unit shape in the unit geometry's frame:
// the unit sphere for spheres and ellipsoids, the unit geometry's bounding box otherwise (exact
// for boxes, the enclosing box for cylinders and capsules).
// bodies: [{ placed, p (p_WBo), q (q_WB), radius (bounding sphere about Bo), shape4 (the unit
// geometry in B), unit: { round, box (Box3 of the unit geometry) } }]. Returns { body, point (W) }
// of the nearest hit, or null.
export function pickBodies(ray, bodies) {
  const { X, Xinv, hit, sphere, one } = scratch;
  let best = null, bestDistance = Infinity;
  for (const b of bodies) {
    if (!b.placed || !b.unit) continue;
    sphere.center.copy(b.p);
    sphere.radius = b.radius;
    if (!ray.intersectsSphere(sphere)) continue;
    // The ray in the unit geometry's frame U: X_WU = X_WB X_BU, so ray_U = X_WU^-1 ray_W.
    X.compose(b.p, b.q, one).multiply(b.shape4);
    Xinv.copy(X).invert();
    const local = scratch.ray.copy(ray).applyMatrix4(Xinv);
    const found = b.unit.round ? local.intersectSphere(sphere.set(sphere.center.set(0, 0, 0), 1), hit)
                               : local.intersectBox(b.unit.box, hit);
    if (!found) continue;
    hit.applyMatrix4(X);  // back to W
    const distance = hit.distanceTo(ray.origin);
    if (distance < bestDistance) {
      bestDistance = distance;
      best = { body: b, point: hit.clone() };
    }
  }
  return best;
}

// The placed body under the raycaster's ray among `bodies` (bodies.js), and the hit point in W:
// { body, point }, or null.
export function pick(raycaster, bodies) {
  if (bodies.impostors) return pickBodies(raycaster.ray, bodies.list);
  const hit = raycaster.intersectObjects(bodies.instanced.map((g) => g.mesh), false)
    .find((h) => h.instanceId !== undefined);
  if (!hit) return null;
  const g = bodies.instanced.find((x) => x.mesh === hit.object);
  const body = g ? bodies.byId.get(g.ids[hit.instanceId]) : null;
  return body && body.placed ? { body, point: hit.point } : null;
}
