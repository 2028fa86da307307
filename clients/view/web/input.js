// The pointer over the 3D view: the left button pressed on a body and dragged pushes it (push.js);
// pressed and released in place, it selects the body; hovering shows the body's axes (x red,
// y green, z blue: B), sized to the body. The orbit controls (viewport.js) take the drags that
// start off the bodies.
import * as THREE from 'three';

import { pick } from './picking.js';

const kClickSlop = 4;  // CSS px a click may move and still select

export class PointerInput {
  // container: the canvas's (the canvas itself is replaced when multisampling changes);
  // viewport, bodies, push, selection, connection: the page's (viewport.js, bodies.js, push.js,
  // selection.js, connection.js).
  constructor(container, { viewport, bodies, push, selection, connection }) {
    this.viewport = viewport;
    this.bodies = bodies;
    this.push = push;
    this.selection = selection;
    this.connection = connection;
    this.hovered = null;        // the body under the pointer, picked once per frame
    this.hoverPending = false;  // the pointer moved since
    this.clicked = null;        // { body, x, y }: a press on a body; released in place, it selects
    this.axes = new THREE.AxesHelper(1);
    this.axes.visible = false;
    viewport.scene.add(this.axes);
    container.addEventListener('pointerdown', (event) => this.down(event));
    container.addEventListener('pointermove', (event) => this.move(event));
    container.addEventListener('pointerup', (event) => this.up(event));
    container.addEventListener('pointercancel', () => this.release());
  }

  // The body at a point of the page (CSS px) and the hit in W ({ body, point }), or null.
  bodyAt(x, y) {
    return pick(this.viewport.rayAt(x, y), this.bodies);
  }

  down(event) {
    if (event.button !== 0) return;
    const b = this.bodyAt(event.clientX, event.clientY);
    this.clicked = b ? { body: b.body, x: event.clientX, y: event.clientY } : null;
    // (Read-only pages and playback select, never push.)
    if (!b || this.connection.readOnly || this.connection.mode === 'playback') return;
    this.push.start(b.body, b.point);
    this.connection.watch();  // (the pulled body's velocities, in a large scene)
    this.viewport.controls.enabled = false;
    this.viewport.canvas.setPointerCapture(event.pointerId);
  }

  move(event) {
    const raycaster = this.viewport.rayAt(event.clientX, event.clientY);
    if (!this.push.active) {
      this.hoverPending = true;  // picked once per frame, not per event
      return;
    }
    this.push.drag(raycaster.ray);
  }

  up(event) {
    const c = this.clicked;
    if (c && Math.hypot(event.clientX - c.x, event.clientY - c.y) < kClickSlop) this.selection.set(c.body);
    this.clicked = null;
    this.release();
  }

  release() {
    const pulling = this.push.active;
    this.push.release();
    if (pulling) this.connection.watch();
    this.viewport.controls.enabled = true;
  }

  // Once per animation frame: the body under the pointer (if it moved), and its axes.
  updateHover() {
    if (this.hoverPending) {
      this.hoverPending = false;
      const h = pick(this.viewport.raycaster, this.bodies);
      this.hovered = h ? h.body : null;
    }
    const b = this.hovered && this.hovered.placed ? this.hovered : null;
    this.axes.visible = !!b;
    if (!b) return;
    this.axes.position.copy(b.p);
    this.axes.quaternion.copy(b.q);
    this.axes.scale.setScalar(Math.max(1.6 * b.radius, 0.05));
  }

  // A new scene: nothing hovered.
  newScene() {
    this.hovered = null;
  }
}
