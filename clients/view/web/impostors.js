// Large scenes (more than kManyBodies bodies, shapes.js): every body of a shape group one quad in
// one BufferGeometry (one draw call), posed in the vertex shader from a float texture of per-body
// position and orientation that each state rewrites (one small upload: 32 bytes a body), its true
// shape ray-cast per pixel (impostor_shaders.js says how). Why not instancing: Chromium's software
// renderer (SwiftShader) draws an instanced mesh about as slowly as one draw per instance
// (bench/notes/view.md).
import * as THREE from 'three';

import { kImpostorFragment, kImpostorVertex, kPoseWidth } from './impostor_shaders.js';
import { capsuleDims } from './shapes.js';

export class ImpostorBodies {
  // n: the scene's bodies (slots 0..n-1).
  constructor(n) {
    this.n = n;
    const rows = Math.max(1, Math.ceil((2 * n) / kPoseWidth));
    this.poses = new Float32Array(kPoseWidth * rows * 4);
    this.texture = new THREE.DataTexture(this.poses, kPoseWidth, rows, THREE.RGBAFormat, THREE.FloatType);
    this.texture.minFilter = THREE.NearestFilter;
    this.texture.magFilter = THREE.NearestFilter;
    this.texture.generateMipmaps = false;
    this.texture.needsUpdate = true;
    this.meshes = [];
    this.count = 0;  // bodies drawn
  }

  // One draw call (kImpostorVertex) for `members` ([{ slot, extent (Vector3: the half-extents in
  // U), frame (Quaternion: q_BU), color }]) of one shape `kind` ('BOX', 'ELLIPSOID', 'CYLINDER' or
  // 'CAPSULE'), opaque or with `opacity`. Returns the mesh.
  add(kind, members, { transparent, opacity }) {
    const n = members.length;
    const slots = new Float32Array(4 * n), extents = new Float32Array(12 * n);
    const frames = new Float32Array(16 * n), colors = new Float32Array(12 * n);
    const index = new Uint32Array(6 * n);
    members.forEach((m, k) => {
      for (let c = 4 * k; c < 4 * k + 4; ++c) {
        slots[c] = m.slot;
        m.extent.toArray(extents, 3 * c);
        m.frame.toArray(frames, 4 * c);
        m.color.toArray(colors, 3 * c);
      }
      // Corners 0 (-1, -1), 1 (1, -1), 2 (-1, 1), 3 (1, 1) on the screen: two triangles, both
      // counter-clockwise (front faces).
      index.set([0, 1, 2, 2, 1, 3].map((c) => 4 * k + c), 6 * k);
    });
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('bodySlot', new THREE.BufferAttribute(slots, 1));
    geometry.setAttribute('extent', new THREE.BufferAttribute(extents, 3));
    geometry.setAttribute('shapeFrame', new THREE.BufferAttribute(frames, 4));
    geometry.setAttribute('color', new THREE.BufferAttribute(colors, 3));
    geometry.setIndex(new THREE.BufferAttribute(index, 1));
    const material = new THREE.ShaderMaterial({
      defines: { [`SHAPE_${kind}`]: '' }, transparent,
      uniforms: { bodyPoses: { value: this.texture }, opacity: { value: opacity } },
      vertexShader: kImpostorVertex, fragmentShader: kImpostorFragment,
    });
    const mesh = new THREE.Mesh(geometry, material);
    mesh.frustumCulled = false;  // placed on the GPU
    this.meshes.push(mesh);
    this.count += n;
    return mesh;
  }

  // The pose of the body in `slot`: p (p_WBo) and q (q_WB), three.js vectors.
  setPose(slot, p, q) {
    const o = 8 * slot, a = this.poses;
    a[o] = p.x;
    a[o + 1] = p.y;
    a[o + 2] = p.z;
    a[o + 3] = 1;  // placed
    a[o + 4] = q.x;
    a[o + 5] = q.y;
    a[o + 6] = q.z;
    a[o + 7] = q.w;
  }

  // After a state's poses: upload the texture with the next frame.
  commit() { this.texture.needsUpdate = true; }

  // The pose the GPU gets for a slot (float32), or null if not placed: { position, orientation
  // (w, x, y, z) }.
  pose(slot) {
    const o = 8 * slot, a = this.poses;
    if (!(slot >= 0 && slot < this.n) || a[o + 3] !== 1) return null;
    return { position: [a[o], a[o + 1], a[o + 2]], orientation: [a[o + 7], a[o + 4], a[o + 5], a[o + 6]] };
  }

  dispose() {
    for (const mesh of this.meshes) {
      mesh.removeFromParent();
      mesh.geometry.dispose();
      mesh.material.dispose();
    }
    this.meshes = [];
    this.texture.dispose();
  }
}

// The impostor shader's kind for a body (kImpostorVertex), the same for every body of a group
// (shapes.js, groupsOf).
export function impostorKind(b) {
  switch (b.shape) {
    case 'sphere': case 'ellipsoid': return 'ELLIPSOID';
    case 'cylinder': return 'CYLINDER';
    case 'capsule': return 'CAPSULE';
    default: return 'BOX';
  }
}
// The body's shape as its impostor draws it: its half-extents in U and q_BU (kImpostorVertex),
// from its unit geometry's scale and frame in B (shapeMatrix) and the unit geometries' sizes
// (geometryOf: unit sphere, unit cube, cylinder of radius 1 and length 1; a capsule unscaled).
export function impostorShape(kind, d, shape4) {
  const extent = new THREE.Vector3(), frame = new THREE.Quaternion();
  shape4.decompose(new THREE.Vector3(), frame, extent);
  if (kind === 'BOX') extent.multiplyScalar(0.5);
  else if (kind === 'CYLINDER') extent.z *= 0.5;
  else if (kind === 'CAPSULE') {
    const [radius, length] = capsuleDims(d);
    extent.set(radius, radius, length / 2 + radius);
  }
  return { extent, frame };
}
