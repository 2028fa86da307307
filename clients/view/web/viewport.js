// The 3D view: the WebGL renderer (remade when multisampling changes), the three.js scene with its
// stage (stage.js: background, grid, axes, lights), the camera and its orbit controls, the render scale (dynamic resolution,
// render_scale.js) and the mapping between the page's pixels and the world.
import * as THREE from 'three';
import { OrbitControls } from './three/OrbitControls.js';

import { RenderScale } from './render_scale.js';
import { makeStage } from './stage.js';

export class Viewport {
  // container: the element the canvas goes in; onChange(): the picture changed (draw_loop.js).
  constructor(container, onChange) {
    this.container = container;
    this.onChange = onChange;
    this.loop = null;  // the animation loop's callback, moved to a new renderer with the canvas
    // The render scale (a fraction of devicePixelRatio): dynamic resolution, so that the page draws
    // at every refresh where WebGL runs on the CPU (render_scale.js says how and what was
    // measured).
    this.scaleControl = new RenderScale();
    this.renderScale = this.scaleControl.scale;
    // Held (a test comparing pixels with a ray cast at a known scale, holdRenderScale): the
    // controller decides nothing, as if the page were hidden, and a new scene keeps the held scale.
    this.renderScaleHeld = false;
    this.renderer = this.makeRenderer(true);
    container.appendChild(this.renderer.domElement);
    // Whether WebGL runs on the CPU: SwiftShader (what Chromium uses on a machine without a usable
    // GPU, and in headless tests) or Mesa's llvmpipe / softpipe. There multisampling is not worth
    // its cost: a software renderer pays it per pixel on the CPUs that rigidd runs on, and the
    // dynamic resolution then lowers the resolution to make up for it (bench/notes/view.md).
    this.softwareGL = (() => {
      const gl = this.renderer.getContext();
      const info = gl.getExtension('WEBGL_debug_renderer_info');
      const name = String(gl.getParameter(info ? info.UNMASKED_RENDERER_WEBGL : gl.RENDERER));
      return /swiftshader|llvmpipe|softpipe/i.test(name);
    })();

    const scene = new THREE.Scene();
    this.scene = scene;
    const camera = new THREE.PerspectiveCamera(50, 1, 0.01, 1000);
    this.camera = camera;
    camera.up.set(0, 0, 1);  // rigid's world: z up
    camera.position.set(3.5, -4.5, 3);
    this.controls = new OrbitControls(camera, this.renderer.domElement);
    this.controls.target.set(0, 0, 0);
    this.controls.update();
    this.stage = makeStage(scene);  // background, grid, world axes, lights (stage.js)

    this.raycaster = new THREE.Raycaster();
    this.pointer = new THREE.Vector2();
    window.addEventListener('resize', () => this.resize());
  }

  makeRenderer(antialias) {
    const r = new THREE.WebGLRenderer({ antialias, preserveDrawingBuffer: true });
    r.setPixelRatio(window.devicePixelRatio * this.renderScale);
    return r;
  }

  get canvas() {
    return this.renderer.domElement;
  }

  // The animation loop (three.js's: requestAnimationFrame), or null to stop it.
  setAnimationLoop(frame) {
    this.loop = frame;
    this.renderer.setAnimationLoop(frame);
  }

  // A new scene: its own frame rate decides its render scale; multisampling only for small scenes
  // on a GPU (large: `large`).
  newScene(large) {
    this.scaleControl.reset();
    if (!this.renderScaleHeld) this.setRenderScale(this.scaleControl.scale);
    this.useAntialias(!large && !this.softwareGL);
  }

  // Multisampling is fixed when a WebGL context is made: a new renderer (and canvas) when it
  // changes, the animation loop moved to it.
  useAntialias(on) {
    if (this.renderer.getContextAttributes().antialias === on) return;
    const loop = this.loop;
    this.setAnimationLoop(null);
    const old = this.renderer;
    this.renderer = this.makeRenderer(on);
    old.domElement.replaceWith(this.renderer.domElement);
    this.controls.disconnect();
    this.controls.connect(this.renderer.domElement);
    old.dispose();
    this.resize();
    if (loop && !this.loop) this.setAnimationLoop(loop);
  }

  resize() {
    this.onChange();
    const w = window.innerWidth, h = window.innerHeight;
    this.renderer.setSize(w, h);
    this.camera.aspect = w / Math.max(h, 1);
    this.camera.updateProjectionMatrix();
  }

  render() {
    this.renderer.render(this.scene, this.camera);
  }

  setRenderScale(scale) {
    if (scale === this.renderScale) return;
    this.renderScale = scale;
    this.renderer.setPixelRatio(window.devicePixelRatio * this.renderScale);
    this.resize();
  }

  // Dynamic resolution (render_scale.js): one decision per second of frames, only while the page
  // is shown (a hidden page gets no frames to count).
  adaptRenderScale(now, drawn) {
    // (Frames not drawn (redraw.js) say nothing of what drawing costs: the window starts again.)
    const judged = document.visibilityState === 'visible' && !this.renderScaleHeld && drawn;
    const scale = this.scaleControl.frame(now, judged);
    if (!this.renderScaleHeld) this.setRenderScale(scale);
  }

  // Renders at `scale` until holdRenderScale(null) hands the scale back to the controller.
  holdRenderScale(scale) {
    if (scale === null) {
      this.renderScaleHeld = false;
      this.setRenderScale(this.scaleControl.scale);
      return;
    }
    if (!(scale > 0 && scale <= 1)) throw new RangeError(`holdRenderScale: expected a scale in (0, 1] or null, got ${scale}`);
    this.renderScaleHeld = true;
    this.setRenderScale(scale);
    this.onChange();  // (a frame at the held scale, even if it was the scale already)
  }

  // The raycaster along the camera's ray through a point of the page (CSS pixels).
  rayAt(clientX, clientY) {
    const r = this.canvas.getBoundingClientRect();
    this.pointer.set(((clientX - r.left) / r.width) * 2 - 1, -((clientY - r.top) / r.height) * 2 + 1);
    this.raycaster.setFromCamera(this.pointer, this.camera);
    return this.raycaster;
  }

  // Where a point of the world (Vector3, W) is on the page, in CSS pixels.
  screenOf(p_W) {
    const r = this.canvas.getBoundingClientRect();
    const s = p_W.clone().project(this.camera);
    return { x: r.left + (s.x + 1) / 2 * r.width, y: r.top + (1 - s.y) / 2 * r.height };
  }

  // The camera moved by `delta` (W), keeping its view (follows a body).
  translate(delta) {
    this.controls.target.add(delta);
    this.camera.position.add(delta);
  }
}
