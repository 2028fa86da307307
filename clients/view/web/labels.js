// Names on the view: the body under the pointer named next to it (a tooltip, always), and with
// "names" on, every body's name at its centre, for at most kMaxLabels bodies (the selected and the
// hovered first, then the scene's order): beyond that many, names would hide the scene and cost
// the page a DOM update each per frame.
import * as THREE from 'three';

const kMaxLabels = 64;
const scratch = new THREE.Vector3();

export class Labels {
  // container: the element over the view the names go in; viewport (viewport.js); bodies
  // (bodies.js); wanted(): the bodies named first (selected, hovered).
  constructor(container, viewport, bodies, wanted) {
    this.container = container;
    this.viewport = viewport;
    this.bodies = bodies;
    this.wanted = wanted;
    this.on = false;
    this.tip = element('label tip');
    this.tip.hidden = true;
    container.appendChild(this.tip);
    this.pool = [];      // name elements, reused
    this.shown = [];     // the names shown now (window.rigidView.labels)
  }

  toggle(on = !this.on) {
    this.on = on;
  }

  newScene() {
    this.tip.hidden = true;
    for (const e of this.pool) e.hidden = true;
    this.shown = [];
  }

  // Once per animation frame: the tooltip at the hovered body, the names at their bodies.
  update(hovered) {
    this.place(this.tip, hovered, hovered ? `${hovered.name} (id ${hovered.id})` : '', 'translate(14px, 10px)');
    const shown = [];
    if (this.on) {
      const first = this.wanted().filter((b) => b && b.placed);
      const chosen = new Set(first);
      for (const b of this.bodies.list) {
        if (chosen.size >= kMaxLabels) break;
        if (b.placed) chosen.add(b);
      }
      let k = 0;
      for (const b of chosen) {
        const e = this.pool[k] || (this.pool[k] = this.container.appendChild(element('label name')));
        if (this.place(e, b, b.name, 'translate(-50%, -50%)')) shown.push(b.name);
        k += 1;
      }
      for (; k < this.pool.length; ++k) this.pool[k].hidden = true;
    } else {
      for (const e of this.pool) e.hidden = true;
    }
    this.shown = shown;
  }

  // Puts `e` at body b's centre on the page, moved by `offset` (a CSS transform), hidden if b is
  // null or behind the camera; whether it is shown.
  place(e, b, text, offset) {
    const camera = this.viewport.camera;
    if (!b || !b.placed || scratch.copy(b.p).applyMatrix4(camera.matrixWorldInverse).z > -camera.near) {
      e.hidden = true;
      return false;
    }
    const at = this.viewport.screenOf(b.p);
    if (e.textContent !== text) e.textContent = text;
    e.style.transform = `translate(${Math.round(at.x)}px, ${Math.round(at.y)}px) ${offset}`;
    e.hidden = false;
    return true;
  }
}

function element(className) {
  const e = document.createElement('div');
  e.className = className;
  return e;
}
