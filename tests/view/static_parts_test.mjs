// The page's static parts (clients/view/web/static_parts.js) from a scene message's "parts", in
// node with three.js: a plane drawn as a square in its frame (its origin at p, its normal the
// frame's z), a box at its pose scaled to its size, a cylinder along the frame's z; a scene
// without parts draws none, and a new scene replaces the old parts.
// usage: node static_parts_test.mjs
import assert from 'node:assert/strict';
// three.js as the page's module resolves it (clients/view/web's npm packages).
import * as THREE from '../../clients/view/web/node_modules/three/build/three.module.js';
import { StaticParts } from '../../clients/view/web/static_parts.js';
import { test, done } from './unit.mjs';

const near = (a, b, what) => assert.ok(a.distanceTo(b) < 1e-12, `${what}: ${a.toArray()} != ${b.toArray()}`);
const at = (mesh, x, y, z) => new THREE.Vector3(x, y, z).applyMatrix4(mesh.matrix);

// A wall x = 2 (normal -x: z of its frame turned onto -x, a quarter turn about y), a box 1 x 2 x
// 0.5 turned a half turn about z, a cylinder of radius 0.1 and length 0.4.
const s = Math.SQRT1_2;
const msg = {
  bodies: [],
  parts: [
    { name: 'wall', shape: 'plane', p: [2, 0, 0], q: [s, 0, -s, 0], dims: [0, 0, 0] },
    { name: 'ramp', shape: 'box', p: [1, 2, 3], q: [0, 0, 0, 1], dims: [1, 2, 0.5] },
    { name: 'post', shape: 'cylinder', p: [0, 0, 1], q: [1, 0, 0, 0], dims: [0.1, 0.4, 0] },
  ],
};

test('each part is drawn where the scene has it', () => {
  const scene = new THREE.Scene();
  const parts = new StaticParts(scene);
  parts.build(msg);
  assert.deepEqual(parts.names, ['wall', 'ramp', 'post']);
  const [wall, ramp, post] = parts.group.children;
  // The plane: its square lies in z = 0 of its frame, which is x = 2 in the world.
  near(at(wall, 0, 0, 0), new THREE.Vector3(2, 0, 0), 'plane origin');
  const n = new THREE.Vector3(0, 0, 1).transformDirection(wall.matrix);
  near(n, new THREE.Vector3(-1, 0, 0), 'plane normal');
  wall.geometry.computeBoundingBox();
  assert.equal(wall.geometry.boundingBox.max.z, 0);
  // The box: the unit cube's corner (0.5, 0.5, 0.5) at half its size, turned about z, at p.
  near(at(ramp, 0.5, 0.5, 0.5), new THREE.Vector3(1 - 0.5, 2 - 1, 3 + 0.25), 'box corner');
  // The cylinder: along z, its top at half its length above p.
  post.geometry.computeBoundingBox();
  const top = post.geometry.boundingBox.max.clone().applyMatrix4(post.matrix);
  assert.ok(Math.abs(top.z - 1.2) < 1e-12 && Math.abs(top.x - 0.1) < 1e-12, `cylinder top ${top.toArray()}`);
  assert.ok(scene.children.includes(parts.group));
});

test('a scene without parts draws none, and a new scene replaces the old parts', () => {
  const parts = new StaticParts(new THREE.Scene());
  parts.build(msg);
  parts.build({ bodies: [] });
  assert.equal(parts.group.children.length, 0);
  assert.deepEqual(parts.names, []);
  parts.build({ bodies: [], parts: [msg.parts[1]] });
  assert.deepEqual(parts.names, ['ramp']);
});

done();
