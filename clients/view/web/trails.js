// Trails: the last kTrailPoints positions of at most kMaxTrails bodies (the selected one, the
// hovered one, then the first in scene order), each a fixed-size buffer; off unless ticked.
import * as THREE from 'three';

import { colorOf } from './shapes.js';

const kMaxTrails = 16;
const kTrailPoints = 256;
const $ = (id) => document.getElementById(id);

export class Trails {
  // scene: where they are drawn; bodies (bodies.js); following(): the bodies whose trails come
  // first (selected, hovered; null when none).
  constructor(scene, bodies, following) {
    this.scene = scene;
    this.bodies = bodies;
    this.following = following;
    this.trails = new Map();  // id -> { line, xyz: Float32Array, count }
    this.lastSimTime = -Infinity;
    $('trails').onchange = () => { if (!$('trails').checked) this.clear(); };
  }

  clear() {
    for (const t of this.trails.values()) this.remove(t);
    this.trails.clear();
  }

  remove(t) {
    this.scene.remove(t.line);
    t.line.geometry.dispose();
    t.line.material.dispose();
  }

  wanted() {
    const out = new Set();
    if (!$('trails').checked) return out;
    for (const b of this.following()) if (b) out.add(b);
    const list = this.bodies.list;
    for (let i = 0; i < list.length && out.size < kMaxTrails; ++i) out.add(list[i]);
    return out;
  }

  // After each state: its positions added (a reset, sim time going back, starts them again).
  add(simTime) {
    if (simTime < this.lastSimTime) this.clear();  // reset: the trails would jump
    this.lastSimTime = simTime;
    const want = this.wanted();
    for (const [id, t] of this.trails) {
      if (![...want].some((b) => b.id === id)) {
        this.remove(t);
        this.trails.delete(id);
      }
    }
    for (const b of want) {
      if (!b.placed) continue;
      let t = this.trails.get(b.id);
      if (!t) {
        const xyz = new Float32Array(3 * kTrailPoints);
        const geometry = new THREE.BufferGeometry();
        geometry.setAttribute('position', new THREE.BufferAttribute(xyz, 3).setUsage(THREE.DynamicDrawUsage));
        const line = new THREE.Line(geometry, new THREE.LineBasicMaterial({
          color: colorOf(b.index), transparent: true, opacity: 0.7 }));
        line.frustumCulled = false;
        this.scene.add(line);
        t = { line, xyz, count: 0 };
        this.trails.set(b.id, t);
      }
      if (t.count === kTrailPoints) t.xyz.copyWithin(0, 3);  // full: drop the oldest
      else t.count += 1;
      t.xyz.set([b.p.x, b.p.y, b.p.z], 3 * (t.count - 1));
      t.line.geometry.attributes.position.needsUpdate = true;
      t.line.geometry.setDrawRange(0, t.count);
    }
  }

  get count() {
    return this.trails.size;
  }
}
