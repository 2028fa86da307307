// What each body looks like: its unit geometry, the matrix that scales that geometry to the body's
// dims within B, its colour, and which bodies share one mesh (geometryKey). The scene message
// describes the shapes (protocol.hpp, scene_json).
import * as THREE from 'three';

// Scenes of more than kManyBodies bodies are drawn for speed: without multisampling, with Lambert
// instead of physically based shading, each body as one ray-cast quad (impostors.js) instead of an
// instanced mesh. In a software renderer (SwiftShader: headless Chromium, machines without a GPU)
// multisampling and physically based shading cost a large scene much of its frame rate, and an
// instanced mesh's cost is per instance, a merged mesh's per vertex, an impostor's (4 vertices)
// mostly per pixel (bench/notes/view.md).
export const kManyBodies = 256;

export const palette = [0x4fc3f7, 0xffb74d, 0x81c784, 0xe57373, 0xba68c8, 0xfff176, 0x90a4ae];
export const colorOf = (index) => palette[index % palette.length];

const positive = (v, fallback) => (Number.isFinite(v) && v > 0 ? v : fallback);

// What a shape's instances share: a unit geometry (sphere and ellipsoid: the unit sphere; box: the
// unit cube; cylinder: radius 1, length 1 along z), which shapeMatrix() scales to each body's dims,
// so that bodies of one shape are one InstancedMesh (one draw call) whatever their sizes. A
// capsule's round ends cannot be scaled unevenly: capsules share a geometry only with equal dims.
// Rounder when there are few (in software rendering every triangle of every instance costs).
export function geometryOf(b, count = 1) {
  const fine = count <= 32 ? 2 : count <= kManyBodies ? 1 : 0;
  const round = [8, 16, 32][fine];
  let g;
  switch (b.shape) {
    case 'sphere':
    case 'ellipsoid':
      return new THREE.SphereGeometry(1, round, round / 2);
    case 'cylinder':
      g = new THREE.CylinderGeometry(1, 1, 1, round);
      g.rotateX(Math.PI / 2);  // three's axis is y, rigid's is z
      return g;
    case 'capsule': {
      const [radius, length] = capsuleDims(b);
      g = new THREE.CapsuleGeometry(radius, length, [2, 4, 8][fine], round);
      g.rotateX(Math.PI / 2);
      return g;
    }
    default:
      return new THREE.BoxGeometry(1, 1, 1);
  }
}

// A capsule's radius and the length of its cylinder (between the centres of its round ends).
export function capsuleDims(b) {
  const d = b.dims || [];
  return [positive(d[0], 0.05), positive(d[1], 0.1)];
}

// The shape within B: the unit geometry scaled to the body's dims; the box of a body's principal
// moments also turned to its principal axes (frame: w, x, y, z in B).
export function shapeMatrix(b) {
  const d = b.dims || [0.1, 0.1, 0.1];
  const m = new THREE.Matrix4();
  switch (b.shape) {
    case 'sphere': {
      const r = positive(d[0], 0.05);
      return m.makeScale(r, r, r);
    }
    case 'ellipsoid': return m.makeScale(positive(d[0], 0.05), positive(d[1], 0.05), positive(d[2], 0.05));
    case 'cylinder': {
      const r = positive(d[0], 0.05);
      return m.makeScale(r, r, positive(d[1], 0.1));
    }
    case 'capsule': return m;
    default: {
      m.makeScale(positive(d[0], 0.1), positive(d[1], 0.1), positive(d[2], 0.1));
      if (!b.frame) return m;
      const [w, x, y, z] = b.frame;
      return new THREE.Matrix4().makeRotationFromQuaternion(new THREE.Quaternion(x, y, z, w).normalize())
        .multiply(m);
    }
  }
}

// The key of a body's geometry: bodies with the same key share one mesh (translucent boxes of
// moments apart from solid boxes).
function geometryKey(b) {
  const kind = b.shape === 'ellipsoid' ? 'sphere' : b.shape;
  return JSON.stringify(kind === 'capsule' ? [kind, b.dims] : [kind, !!b.from_moments]);
}

// The scene's bodies by geometryKey: key -> { b (the first body), members (scene indices) }.
export function groupsOf(msg) {
  const groups = new Map();
  msg.bodies.forEach((b, i) => {
    const key = geometryKey(b);
    if (!groups.has(key)) groups.set(key, { b, members: [] });
    groups.get(key).members.push(i);
  });
  return groups;
}

// How a group is drawn: boxes of moments translucent.
export const lookOf = (b) => ({ transparent: !!b.from_moments, opacity: b.from_moments ? 0.6 : 1 });
