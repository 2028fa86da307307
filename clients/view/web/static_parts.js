// The scene's static parts (planes and static shapes, from the scene message's "parts"), drawn
// where they are and never moved: a plane as a translucent square around the point of it nearest
// the origin (it is z = 0 of its frame, solid below), a shape as a body's shape (shapes.js) at its
// pose, in a neutral grey so that they read as the world, not as bodies.
import * as THREE from 'three';
import { geometryOf, shapeMatrix } from './shapes.js';

const kPlaneSize = 20;  // m: a plane's square, centred on its frame's origin

export class StaticParts {
  constructor(scene) {
    this.scene = scene;
    this.group = new THREE.Group();
    scene.add(this.group);
    this.plane = new THREE.MeshStandardMaterial({ color: 0x8d9aa6, transparent: true, opacity: 0.35,
                                                   side: THREE.DoubleSide, depthWrite: false });
    this.solid = new THREE.MeshStandardMaterial({ color: 0x9e9e9e, roughness: 0.9 });
    this.names = [];
  }

  clear() {
    for (const m of this.group.children) m.geometry.dispose();
    this.group.clear();
    this.names = [];
  }

  build(msg) {
    this.clear();
    for (const part of msg.parts || []) {
      const p = part.p || [0, 0, 0];
      const [w, x, y, z] = part.q || [1, 0, 0, 0];
      const pose = new THREE.Matrix4().compose(new THREE.Vector3(p[0], p[1], p[2]),
                                               new THREE.Quaternion(x, y, z, w).normalize(),
                                               new THREE.Vector3(1, 1, 1));
      let mesh;
      if (part.shape === 'plane') {
        mesh = new THREE.Mesh(new THREE.PlaneGeometry(kPlaneSize, kPlaneSize), this.plane);
        mesh.matrix.copy(pose);
      } else {
        mesh = new THREE.Mesh(geometryOf(part), this.solid);
        mesh.matrix.copy(pose).multiply(shapeMatrix(part));
      }
      mesh.matrixAutoUpdate = false;
      mesh.name = part.name;
      this.group.add(mesh);
      this.names.push(part.name);
    }
  }
}
