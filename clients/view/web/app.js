// rigid-view's page: draws rigidd's bodies from SceneInfo and the binary state frames rigid-view
// sends (protocol.hpp), shows Stats, sends pause/resume/step/reset and pushes (drag a body), draws
// the accepted wrenches as arrows (forces) and circular arrows (torques), live or recorded, a
// body list with the selected body's state, trails, and plots of energy and angular-momentum
// drift (drift.js) and of tick lateness.
// window.rigidView exposes what is drawn, for tests and for the console.
import * as THREE from 'three';
import { OrbitControls } from '/three/OrbitControls.js';
import { DriftTable } from '/drift.js';
import { StripChart } from '/plot.js';
import { WorkerSocket } from '/worker_socket.js';
import { RenderScale } from '/render_scale.js';
import { Redraw } from '/redraw.js';
import { createTimeline } from '/timeline.js';  // playback (rigid-view FILE)
import { decodeState, kAckCommand, kMaxSteps, kMaxWrenchesShown, kWatchLifetime } from '/protocol.js';

// The watch is re-sent while it holds, three times in rigid-view's lifetime of it.
const kWatchEvery = (kWatchLifetime * 1000) / 3;  // ms
const $ = (id) => document.getElementById(id);

// Scenes of more than kManyBodies bodies are drawn for speed: without multisampling, with Lambert
// instead of physically based shading, each body as one ray-cast quad (ImpostorBodies, below)
// instead of an instanced mesh. Measured in headless Chromium's software renderer
// (bench/view/README.md), 10^3 bodies: multisampling halves the frame rate, PBR shading costs a
// third; SwiftShader's cost is per instance, that of one merged mesh per vertex, an impostor's
// (4 vertices) mostly per pixel.
const kManyBodies = 256;
// The render scale (a fraction of devicePixelRatio): dynamic resolution, so that the page draws at
// every refresh where WebGL runs on the CPU (render_scale.js says how and what was measured).
const renderScaleControl = new RenderScale();
let renderScale = renderScaleControl.scale;
// Held (a test comparing pixels with a ray cast at a known scale, debug.holdRenderScale): the
// controller decides nothing, as if the page were hidden, and a new scene keeps the held scale.
let renderScaleHeld = false;
// Draw on change (redraw.js): a frame renders only when something it shows changed, reported by
// wake(); a paused scene under a still camera costs no rendering. Nor animation frames: after a
// frame with nothing to draw the loop stops (frame), and starts again (ensureLoop) on a wake, on
// any message from rigid-view (a state to apply and acknowledge, Stats for the plot) and for the
// heartbeat; between them Chromium calls nothing of the page 60 times a second.
const redraw = new Redraw();
let looping = false;
function ensureLoop() {
  if (looping) return;
  looping = true;
  renderer.setAnimationLoop(frame);
}
function stopLoop() {
  renderer.setAnimationLoop(null);
  looping = false;
}
const wake = () => {
  redraw.wake(performance.now());
  ensureLoop();
};
setInterval(ensureLoop, redraw.heartbeat / 2);
// Any input on the page may change the picture (the camera, a hover, a checkbox, the body list):
// the frames that follow are drawn. Capture phase, so that no handler can stop it.
for (const type of ['pointerdown', 'pointermove', 'pointerup', 'wheel', 'keydown', 'keyup', 'input',
                    'change', 'click', 'resize', 'focus'])
  window.addEventListener(type, wake, { capture: true, passive: true });
document.addEventListener('visibilitychange', wake);
function makeRenderer(antialias) {
  const r = new THREE.WebGLRenderer({ antialias, preserveDrawingBuffer: true });
  r.setPixelRatio(window.devicePixelRatio * renderScale);
  return r;
}
let renderer = makeRenderer(true);
$('view').appendChild(renderer.domElement);
// Whether WebGL runs on the CPU: SwiftShader (what Chromium uses on a machine without a usable GPU,
// and in headless tests) or Mesa's llvmpipe / softpipe. There multisampling is not worth its cost:
// a software renderer pays it per pixel on the CPUs that rigidd runs on. Measured in headless
// Chromium on a 2-core machine (bench/view/README.md), the default scene at render scale 0.5:
// Chromium 142-154% of a CPU with 4x MSAA, 101-104% without.
const softwareGL = (() => {
  const gl = renderer.getContext();
  const info = gl.getExtension('WEBGL_debug_renderer_info');
  const name = String(gl.getParameter(info ? info.UNMASKED_RENDERER_WEBGL : gl.RENDERER));
  return /swiftshader|llvmpipe|softpipe/i.test(name);
})();
// Multisampling is fixed when a WebGL context is made: a new renderer (and canvas) when it changes.
function useAntialias(on) {
  if (renderer.getContextAttributes().antialias === on) return;
  stopLoop();
  const old = renderer;
  renderer = makeRenderer(on);
  old.domElement.replaceWith(renderer.domElement);
  controls.disconnect();
  controls.connect(renderer.domElement);
  old.dispose();
  resize();
  ensureLoop();
}
const scene = new THREE.Scene();
scene.background = new THREE.Color(0x1d1f24);
const camera = new THREE.PerspectiveCamera(50, 1, 0.01, 1000);
camera.up.set(0, 0, 1);  // rigid's world: z up
camera.position.set(3.5, -4.5, 3);
const controls = new OrbitControls(camera, renderer.domElement);
controls.target.set(0, 0, 0);
controls.update();
const grid = new THREE.GridHelper(10, 20, 0x666666, 0x3a3a3a);
grid.rotation.x = Math.PI / 2;  // the x-y plane
scene.add(grid);
scene.add(new THREE.AxesHelper(1));
scene.add(new THREE.HemisphereLight(0xffffff, 0x404040, 2.0));
const sun = new THREE.DirectionalLight(0xffffff, 1.5);
sun.position.set(3, -2, 5);
scene.add(sun);

// Bodies are drawn with one mesh per shape (geometryKey): a scene of 10^4 spheres of any sizes is
// one draw call. Small scenes: a THREE.InstancedMesh, each body an instance whose matrix is its
// pose from the state frame times its shape's scale and frame in B. Scenes of more than
// kManyBodies bodies: ImpostorBodies (below), every body one quad, posed and ray-cast on the GPU.
// id -> { id, name, shape, index (scene order), group, instance (small scenes), mass, inertia,
//        radius, shape4 (the unit geometry's scale and frame in B), unit (large scenes: the unit
//        shape picked against), p (p_WBo), q (q_WB), v (v_WBo in W), w (w_WB in W), placed }
const bodies = new Map();
let bodyList = [];         // in scene order
const bodyGroup = new THREE.Group();
scene.add(bodyGroup);
const instanced = [];      // { mesh, ids: Int32Array (instance -> body id) }
let impostors = null;      // ImpostorBodies, for scenes of more than kManyBodies bodies
const debug = {
  connected: false, readOnly: false, connection: 0, scene: null, bodies: [], stats: null,
  frames: 0, lastState: null, replies: [], errors: [], pushes: 0,
  // The pose drawn for a body: position and orientation (w, x, y, z), and the tick it came from.
  renderedPose(name) {
    // (Small scenes: the pose handed to three.js, in double precision; the GPU gets it as float32.
    // Large scenes: the float32 pose in the texture the impostors' vertex shader reads.)
    for (const b of bodies.values()) {
      if (b.name !== name || !b.placed) continue;
      if (impostors) {
        const drawn = impostors.pose(b.index);
        return drawn && { tick: debug.lastState ? debug.lastState.tick : -1, ...drawn };
      }
      const p = b.p, q = b.q;
      return { tick: debug.lastState ? debug.lastState.tick : -1,
               position: [p.x, p.y, p.z], orientation: [q.w, q.x, q.y, q.z] };
    }
    return null;
  },
  // A body's last published state as the page holds it (velocities in W; null in a large live
  // scene unless the body is selected: pose frames carry the watched bodies' only).
  bodyState(name) {
    for (const b of bodies.values()) {
      if (b.name !== name || !b.placed) continue;
      return { id: b.id, tick: debug.lastState ? debug.lastState.tick : -1,
               position: b.p.toArray(), orientation: [b.q.w, b.q.x, b.q.y, b.q.z],
               linear_velocity: b.moving ? b.v.toArray() : null,
               angular_velocity: b.moving ? b.w.toArray() : null };
    }
    return null;
  },
  // Selects a body by name (as a click on it or its row does), or none; whether it was found.
  select(name) {
    const b = name === null ? null : bodyList.find((x) => x.name === name);
    if (b === undefined) return false;
    select(b);
    return true;
  },
  // A body's relative drift of energy and angular momentum since its reference state, as
  // rigid-view sends it (clients/view/drift.hpp).
  drift(name) {
    const b = bodyList.find((x) => x.name === name);
    return b ? drift.worst(b.index) : null;
  },
  // The body that picking finds at a point of the page (CSS pixels), by name, or null.
  bodyAt(x, y) {
    setPointer({ clientX: x, clientY: y });
    const h = pick();
    return h ? h.body.name : null;
  },
  // The body whose axes are drawn (under the pointer), the followed camera target.
  hovered() { return hoverAxes.visible && hovered ? hovered.name : null; },
  target() { return controls.target.toArray(); },
  cameraPosition() { return camera.position.toArray(); },
  // Where a body's centre (plus `offset`, in W) is on the screen, in CSS pixels of the page.
  screenOf(name, offset = [0, 0, 0]) {
    const b = bodyList.find((x) => x.name === name);
    if (!b || !b.placed) return null;
    const r = renderer.domElement.getBoundingClientRect();
    const s = b.p.clone().add(new THREE.Vector3(...offset)).project(camera);
    return { x: r.left + (s.x + 1) / 2 * r.width, y: r.top + (1 - s.y) / 2 * r.height };
  },
  // The wrench arrows drawn now: [{ body, from (W), force (W) }].
  arrows: [],
  // The torque arrows drawn now: [{ body, center (p_WBo), torque (W), axis (unit, W), radius,
  // tip (the cone's base on the arc, W), tipDirection (where the cone points, W) }].
  torques: [],
  // Samples the plots received, and the last ones.
  plots() {
    return { drift: driftChart.received, lateness: latenessChart.received,
             lastDrift: driftChart.last(), lastLateness: latenessChart.last(),
             of: selected ? selected.name : 'all (max)' };
  },
  // How many bodies the meshes draw, how many meshes (draw calls) that takes, and how: 'instanced'
  // (small scenes) or 'impostors' (ImpostorBodies).
  instances() {
    if (impostors) return { meshes: impostors.meshes.length, count: impostors.count, path: 'impostors' };
    let count = 0;
    for (const g of instanced) count += g.mesh.count;
    return { meshes: instanced.length, count, path: 'instanced' };
  },
};
window.rigidView = debug;
debug.softwareGL = softwareGL;
debug.antialias = () => renderer.getContextAttributes().antialias;

const palette = [0x4fc3f7, 0xffb74d, 0x81c784, 0xe57373, 0xba68c8, 0xfff176, 0x90a4ae];

// What a shape's instances share: a unit geometry (sphere and ellipsoid: the unit sphere; box: the
// unit cube; cylinder: radius 1, length 1 along z), which shapeMatrix() scales to each body's dims,
// so that bodies of one shape are one InstancedMesh (one draw call) whatever their sizes. A
// capsule's round ends cannot be scaled unevenly: capsules share a geometry only with equal dims.
// Rounder when there are few (in software rendering every triangle of every instance costs).
const positive = (v, fallback) => (Number.isFinite(v) && v > 0 ? v : fallback);
function geometryOf(b, count = 1) {
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
function capsuleDims(b) {
  const d = b.dims || [];
  return [positive(d[0], 0.05), positive(d[1], 0.1)];
}

// The shape within B: the unit geometry scaled to the body's dims; the box of a body's principal
// moments also turned to its principal axes (frame: w, x, y, z in B).
function shapeMatrix(b) {
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

// The key of a body's geometry: bodies with the same key share one InstancedMesh (translucent
// boxes of moments apart from solid boxes).
function geometryKey(b) {
  const kind = b.shape === 'ellipsoid' ? 'sphere' : b.shape;
  return JSON.stringify(kind === 'capsule' ? [kind, b.dims] : [kind, !!b.from_moments]);
}

// Large scenes: every body of a shape group one quad in one BufferGeometry (one draw call), posed
// in the vertex shader from a float texture of per-body position and orientation that each state
// rewrites (one small upload: 32 bytes a body). Why not instancing: Chromium's software renderer
// (SwiftShader) draws an instanced mesh about as slowly as one draw per instance (~0.06 ms each,
// bench/view/README.md).
// (Here rather than in a module of its own: rigid-view serves a fixed list of files, server.cpp.)

// Texels per row of the pose texture; a body takes two (p_WBo, placed) and (q_WB as x, y, z, w),
// side by side in one row because the width is even.
const kPoseWidth = 1024;

// Impostors: each body one screen-facing quad (4 vertices instead of its mesh's 24-60) whose
// fragment shader intersects the view ray with the body's true shape, in the shape's frame U
// (box: slab test; ellipsoid: quadratic; cylinder: quadratic and two planes; capsule: quadratic
// and two spheres), discards misses, shades the hit by its normal and writes its depth, so that
// bodies occlude and cut through each other as meshes do. Why: meshes merged into one draw cost
// SwiftShader per vertex (24-60 a body, two texture fetches each), impostors per pixel, which the
// dynamic resolution lowers (bench/view/README.md). Shading: Lambert per pixel, the light of the
// page's hemisphere (sky white, ground 0x404040, intensity 2, about z) plus its sun (1.5 from
// (3, -2, 5)), times the BRDF colour / pi, as three.js's MeshLambertMaterial computes it.
// The quad lies in the plane through Bo facing the camera, its half-sizes along the screen's axes
// the shape's support (its half-width along that axis, for any orientation), grown by d / (d - s)
// for the part of the body nearer the camera than that plane (d: Bo's distance from the camera,
// s: the support towards it): it covers the body's projection, and mostly not much more. The ray
// is taken from the quad's point (p in U, near the body: float32 keeps the quadratics precise),
// along the camera's ray through it; at its parameter t = -1 it is at the camera.
// Per vertex: the body's slot, its shape's half-extents in U (box: half its edges; ellipsoid: its
// radii; cylinder: radius, radius, half its length; capsule: radius, radius, half its whole
// length, along z) and q_BU; the quad's corner is gl_VertexID's lowest two bits.
const kImpostorVertex = `
uniform highp sampler2D bodyPoses;
attribute float bodySlot;
attribute vec3 extent;
attribute vec4 shapeFrame;
attribute vec3 color;
flat varying vec3 vExtent;
flat varying vec3 vColor;
flat varying vec3 vCamera;         // the camera's position from Bo, in U
flat varying vec3 vUp;             // the hemisphere light's axis (z of W) in U
flat varying vec3 vSun;            // towards the sun, in U
varying vec3 vPoint;               // the quad's point in U
vec3 rotateByQuaternion(vec4 q, vec3 v) { return v + 2.0 * cross(q.xyz, cross(q.xyz, v) + q.w * v); }
vec4 quaternionProduct(vec4 a, vec4 b) {
  return vec4(a.w * b.xyz + b.w * a.xyz + cross(a.xyz, b.xyz), a.w * b.w - dot(a.xyz, b.xyz));
}
// The shape's half-width along the unit direction n (in U).
float support(vec3 n) {
#if defined(SHAPE_BOX)
  return dot(extent, abs(n));
#elif defined(SHAPE_ELLIPSOID)
  return length(extent * n);
#elif defined(SHAPE_CYLINDER)
  return extent.z * abs(n.z) + extent.x * length(n.xy);
#else
  return (extent.z - extent.x) * abs(n.z) + extent.x;
#endif
}
void main() {
  int poseTexel = 2 * int(bodySlot + 0.5);
  ivec2 poseAt = ivec2(poseTexel % ${kPoseWidth}, poseTexel / ${kPoseWidth});
  vec4 bodyP = texelFetch(bodyPoses, poseAt, 0);
  vec4 q_UW = quaternionProduct(texelFetch(bodyPoses, poseAt + ivec2(1, 0), 0), shapeFrame);
  q_UW.xyz = -q_UW.xyz;  // the inverse: W to U
  vec3 toCamera = cameraPosition - bodyP.xyz;
  float d = length(toCamera);
  vec3 w = toCamera / d;
  vec3 u = normalize(cross(vec3(viewMatrix[0][1], viewMatrix[1][1], viewMatrix[2][1]), w));
  vec3 v = cross(w, u);
  vec3 uU = rotateByQuaternion(q_UW, u), vU = rotateByQuaternion(q_UW, v);
  float nearer = support(rotateByQuaternion(q_UW, w));
  // Not placed, or the camera within the body's reach: outside the clip volume, nothing drawn.
  if (bodyP.w == 0.0 || d <= nearer) {
    gl_Position = vec4(0.0, 0.0, 2.0, 1.0);
    return;
  }
  vec2 corner = vec2(float(gl_VertexID & 1), float((gl_VertexID >> 1) & 1)) * 2.0 - 1.0;
  vec2 reach = (d / (d - nearer)) * corner * vec2(support(uU), support(vU));
  gl_Position = projectionMatrix * viewMatrix * vec4(bodyP.xyz + reach.x * u + reach.y * v, 1.0);
  vPoint = reach.x * uU + reach.y * vU;
  vCamera = rotateByQuaternion(q_UW, toCamera);
#if defined(SHAPE_ELLIPSOID)
  // An ellipsoid's ray in the frame where it is the unit sphere.
  vPoint /= extent;
  vCamera /= extent;
#endif
  vUp = rotateByQuaternion(q_UW, vec3(0.0, 0.0, 1.0));
  vSun = rotateByQuaternion(q_UW, vec3(0.4867, -0.3244, 0.8111));
  vExtent = extent;
  vColor = color;
}
`;
const kImpostorFragment = `
uniform mat4 projectionMatrix;
uniform float opacity;
flat varying vec3 vExtent;
flat varying vec3 vColor;
flat varying vec3 vCamera;
flat varying vec3 vUp;
flat varying vec3 vSun;
varying vec3 vPoint;
void main() {
  // The ray p + t dir in U (ellipsoid: scaled to the unit sphere), dir from the camera through p.
  vec3 p = vPoint, dir = vPoint - vCamera, e = vExtent;
  float t;
  vec3 n;
#if defined(SHAPE_BOX)
  vec3 inverse = 1.0 / dir, t0 = (-e - p) * inverse, t1 = (e - p) * inverse;
  vec3 enter = min(t0, t1), leave = max(t0, t1);
  t = max(max(enter.x, enter.y), enter.z);
  if (t > min(min(leave.x, leave.y), leave.z)) discard;
  n = -sign(dir) * vec3(equal(enter, vec3(t)));
#elif defined(SHAPE_ELLIPSOID)
  float a = dot(dir, dir), b = dot(p, dir), disc = b * b - a * (dot(p, p) - 1.0);
  if (disc < 0.0) discard;
  t = (-b - sqrt(disc)) / a;
  n = normalize((p + t * dir) / e);
#else
  // The side: (p.xy + t dir.xy)^2 = r^2 (a ray along the axis: a tiny a, roots far apart).
  float r = e.x, a = max(dot(dir.xy, dir.xy), 1e-12), b = dot(p.xy, dir.xy);
  float disc = b * b - a * (dot(p.xy, p.xy) - r * r);
  if (disc < 0.0) discard;
  float root = sqrt(disc);
  t = (-b - root) / a;
#if defined(SHAPE_CYLINDER)
  // Within the slab |z| <= e.z too: the later entry, if before the earlier exit.
  float t0 = (-e.z - p.z) / dir.z, t1 = (e.z - p.z) / dir.z;
  float capEnter = min(t0, t1);
  if (max(t, capEnter) > min((-b + root) / a, max(t0, t1))) discard;
  n = t > capEnter ? vec3((p.xy + t * dir.xy) / r, 0.0) : vec3(0.0, 0.0, -sign(dir.z));
  t = max(t, capEnter);
#else
  // Entering the infinite cylinder beyond an end, the ray meets that end's sphere or nothing.
  float h = e.z - r, z = p.z + t * dir.z;
  vec3 hit = p + t * dir;
  n = vec3(hit.xy / r, 0.0);
  if (abs(z) > h) {
    vec3 pc = p - vec3(0.0, 0.0, sign(z) * h);
    float a3 = dot(dir, dir), b3 = dot(pc, dir), disc3 = b3 * b3 - a3 * (dot(pc, pc) - r * r);
    if (disc3 < 0.0) discard;
    t = (-b3 - sqrt(disc3)) / a3;
    n = (pc + t * dir) / r;
  }
#endif
#endif
  // Behind the camera (t = -1 is the camera): not seen.
  if (t <= -1.0) discard;
  // The hit's depth: in the camera's frame (1 + t) times the quad point's, -1 / w.
  float viewZ = -(1.0 + t) / gl_FragCoord.w;
  gl_FragDepth = 0.5 * (projectionMatrix[2][2] * viewZ + projectionMatrix[3][2]) / -viewZ + 0.5;
  vec3 irradiance = 2.0 * mix(vec3(0.0513), vec3(1.0), 0.5 * dot(n, vUp) + 0.5) +
                    1.5 * max(dot(n, vSun), 0.0);
  gl_FragColor = vec4(vColor * irradiance * 0.3183098861837907, opacity);
  #include <colorspace_fragment>
}
`;

class ImpostorBodies {
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

// Picking without meshes to ray-cast: the body a ray hits first, from the poses the page holds (the
// same numbers the impostors are drawn from). Each body is first tested against its bounding
// sphere in W (cheap, rejects nearly all of them), then exactly against its unit shape in the unit
// geometry's frame: the unit sphere for spheres and ellipsoids, the unit geometry's bounding box
// otherwise (exact for boxes, the enclosing box for cylinders and capsules).

const pickScratch = {
  X: new THREE.Matrix4(), Xinv: new THREE.Matrix4(), ray: new THREE.Ray(), hit: new THREE.Vector3(),
  sphere: new THREE.Sphere(new THREE.Vector3(), 1), one: new THREE.Vector3(1, 1, 1),
};

// bodies: [{ placed, p (p_WBo), q (q_WB), radius (bounding sphere about Bo), shape4 (the unit
// geometry in B), unit: { round, box (Box3 of the unit geometry) } }]. Returns { body, point (W) }
// of the nearest hit, or null.
function pickBodies(ray, bodies) {
  const { X, Xinv, hit, sphere, one } = pickScratch;
  let best = null, bestDistance = Infinity;
  for (const b of bodies) {
    if (!b.placed || !b.unit) continue;
    sphere.center.copy(b.p);
    sphere.radius = b.radius;
    if (!ray.intersectsSphere(sphere)) continue;
    // The ray in the unit geometry's frame U: X_WU = X_WB X_BU, so ray_U = X_WU^-1 ray_W.
    X.compose(b.p, b.q, one).multiply(b.shape4);
    Xinv.copy(X).invert();
    const local = pickScratch.ray.copy(ray).applyMatrix4(Xinv);
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

const kHidden = new THREE.Matrix4().makeScale(0, 0, 0);  // an instance not yet placed by a state
const scratch = { m: new THREE.Matrix4(), one: new THREE.Vector3(1, 1, 1), c: new THREE.Color() };

function setScene(msg) {
  for (const g of instanced) {
    bodyGroup.remove(g.mesh);
    g.mesh.geometry.dispose();
    g.mesh.material.dispose();
    g.mesh.dispose();
  }
  instanced.length = 0;
  if (impostors) impostors.dispose();
  impostors = null;
  bodies.clear();
  const many = msg.bodies.length > kManyBodies;
  renderScaleControl.reset();  // a new scene: its own frame rate decides
  if (!renderScaleHeld) setRenderScale(renderScaleControl.scale);
  useAntialias(!many && !softwareGL);
  if (many) {
    setImpostorScene(msg, groupsOf(msg));
    return;
  }
  for (const { b, members } of groupsOf(msg).values()) {
    const look = { transparent: !!b.from_moments, opacity: b.from_moments ? 0.6 : 1 };
    const material = new THREE.MeshStandardMaterial({ roughness: 0.6, metalness: 0.1, ...look });
    const geometry = geometryOf(b, 1);
    geometry.computeBoundingSphere();
    const mesh = new THREE.InstancedMesh(geometry, material, members.length);
    mesh.instanceMatrix.setUsage(THREE.DynamicDrawUsage);
    // Bodies move every frame: the instances' bounding sphere would be stale for culling, and is
    // recomputed only when picking needs it.
    mesh.frustumCulled = false;
    const ids = new Int32Array(members.length);
    const g = { mesh, ids };
    members.forEach((i, instance) => {
      const d = msg.bodies[i];
      ids[instance] = d.id;
      const shape = shapeMatrix(d);
      const radius = geometry.boundingSphere.radius * shape.getMaxScaleOnAxis();
      mesh.setMatrixAt(instance, kHidden);
      mesh.setColorAt(instance, scratch.c.setHex(palette[i % palette.length]));
      bodies.set(d.id, { id: d.id, name: d.name, shape: d.shape, index: i, group: g, instance,
                         mass: d.mass, inertia: d.inertia || null, radius, shape4: shape,
                         p: new THREE.Vector3(), q: new THREE.Quaternion(),
                         v: new THREE.Vector3(), w: new THREE.Vector3(), placed: false, moving: false });
    });
    mesh.instanceColor.needsUpdate = true;
    bodyGroup.add(mesh);
    instanced.push(g);
  }
  sceneSet(msg);
}

// The scene's bodies by geometryKey: key -> { b (the first body), members (scene indices) }.
function groupsOf(msg) {
  const groups = new Map();
  msg.bodies.forEach((b, i) => {
    const key = geometryKey(b);
    if (!groups.has(key)) groups.set(key, { b, members: [] });
    groups.get(key).members.push(i);
  });
  return groups;
}

// The impostor shader's kind for a body (kImpostorVertex), the same for every body of a group
// (geometryKey).
function impostorKind(b) {
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
function impostorShape(kind, d, shape4) {
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

// A large scene: one draw of impostors per group, posed on the GPU (ImpostorBodies); the scene
// index is the body's slot in the pose texture. Picking uses pickBodies with each body's unit
// shape, from the unit geometry's bounds (built for that only, never drawn).
function setImpostorScene(msg, groups) {
  impostors = new ImpostorBodies(msg.bodies.length);
  for (const { b, members } of groups.values()) {
    const look = { transparent: !!b.from_moments, opacity: b.from_moments ? 0.6 : 1 };
    const kind = impostorKind(b);
    const geometry = geometryOf(b, members.length);
    geometry.computeBoundingSphere();
    geometry.computeBoundingBox();
    const unit = { round: kind === 'ELLIPSOID', box: geometry.boundingBox };
    const drawn = members.map((i) => {
      const d = msg.bodies[i];
      const shape = shapeMatrix(d);
      bodies.set(d.id, { id: d.id, name: d.name, shape: d.shape, index: i, group: null, instance: -1,
                         mass: d.mass, inertia: d.inertia || null,
                         radius: geometry.boundingSphere.radius * shape.getMaxScaleOnAxis(),
                         shape4: shape, unit, p: new THREE.Vector3(), q: new THREE.Quaternion(),
                         v: new THREE.Vector3(), w: new THREE.Vector3(), placed: false, moving: false });
      return { slot: i, color: new THREE.Color().setHex(palette[i % palette.length]),
               ...impostorShape(kind, d, shape) };
    });
    bodyGroup.add(impostors.add(kind, drawn, look));
    geometry.dispose();
  }
  sceneSet(msg);
}

// What follows a new scene, however it is drawn.
function sceneSet(msg) {
  wake();
  seen = null;
  bodyList = msg.bodies.map((d) => bodies.get(d.id)).filter((b) => b);
  drift.setBodies(msg.bodies.length);
  sceneDt = Number.isFinite(msg.dt) && msg.dt > 0 ? msg.dt : 0;
  wrenches = [];
  select(null);
  hovered = null;
  clearTrails();
  driftChart.clear();
  fillBodyList();
  debug.scene = { name: msg.name, generation: msg.generation, dt: msg.dt };
  debug.bodies = msg.bodies.map((b) => ({ id: b.id, name: b.name, shape: b.shape,
                                          fromMoments: !!b.from_moments }));
  $('scene').textContent = `${msg.name || '(unnamed)'} · ${msg.bodies.length} bodies`;
}

// A state frame (protocol.js decodes it): the bodies placed, their drifts; a pose frame's watched
// bodies then get their whole published state.
function applyState(buffer) {
  const f = decodeState(buffer);
  const n = f.n;
  placeBodies(n, f.ids, f.position, f.orientation, f.linearVelocity, f.angularVelocity);
  if (!f.poses) {
    drift.update(n, slots, f.energyDrift, f.momentumDrift);
  } else {
    const slotOf = (i) => (i >= 0 && i < n ? slots[i] : -1);
    const w = f.worst;
    drift.report({ energy: w.energy, energyAt: slotOf(w.energySlot), momentum: w.momentum,
                   momentumAt: slotOf(w.momentumSlot) });
    for (const r of f.watched) {
      const b = r.slot >= 0 && r.slot < n ? bodies.get(f.ids[r.slot]) : null;
      if (!b) continue;
      const x = r.state;
      b.p.set(x[0], x[1], x[2]);
      b.q.set(x[4], x[5], x[6], x[3]);
      b.v.set(x[7], x[8], x[9]);
      b.w.set(x[10], x[11], x[12]);
      b.moving = true;
      drift.set(b.index, r.energy, r.momentum);
    }
  }
  stateApplied(f.tick, f.simTime, f.stampNs, n, f.generation);
}

// Each body of a state at its pose (and velocities when the frame has them: vel and omega, else
// null); slots[i] becomes state slot i's index in the scene's order (-1: not in the scene).
function placeBodies(n, ids, pos, ori, vel, omega) {
  const { m, one } = scratch;
  if (slots.length !== n) slots = new Int32Array(n);
  if (posesChanged(n, ids, pos, ori)) wake();
  for (let i = 0; i < n; ++i) {
    const b = bodies.get(ids[i]);
    slots[i] = b ? b.index : -1;
    if (!b) continue;
    b.p.set(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]);
    b.q.set(ori[4 * i + 1], ori[4 * i + 2], ori[4 * i + 3], ori[4 * i]);
    if (vel) {
      b.v.set(vel[3 * i], vel[3 * i + 1], vel[3 * i + 2]);
      b.w.set(omega[3 * i], omega[3 * i + 1], omega[3 * i + 2]);
    }
    b.placed = true;
    b.moving = !!vel;
    // Large scenes: the pose into the vertex shader's texture; small: the instance's matrix, X_WB
    // (pose) times the shape's scale and frame in B.
    if (impostors) impostors.setPose(b.index, b.p, b.q);
    else b.group.mesh.setMatrixAt(b.instance, m.compose(b.p, b.q, one).multiply(b.shape4));
  }
}

// Whether a state's poses (ids, positions, orientations) differ from the last state's, which it
// replaces as the one compared against: kept as views of its buffer (each state comes in a buffer
// of its own that nothing changes, worker_socket.js), so a moving scene costs a comparison or two
// and no copy. Exact: a paused scene's states repeat the same numbers. (The watched bodies'
// double-precision records change nothing drawn.)
let seen = null;
function posesChanged(n, ids, pos, ori) {
  const last = seen;
  seen = { ids, pos, ori };
  if (!last || last.ids.length !== n) return true;
  for (let i = 0; i < 4 * n; ++i) if (last.ori[i] !== ori[i]) return true;
  for (let i = 0; i < 3 * n; ++i) if (last.pos[i] !== pos[i]) return true;
  for (let i = 0; i < n; ++i) if (last.ids[i] !== ids[i]) return true;
  return false;
}

// What follows a state, whichever its frame.
function stateApplied(tick, simTime, stampNs, n, generation) {
  // The wrench arrows drawn depend on the tick (acting), as well as on the poses.
  if (wrenches.length && (!debug.lastState || debug.lastState.tick !== tick)) wake();
  if (impostors) impostors.commit();
  for (const g of instanced) {
    g.mesh.instanceMatrix.needsUpdate = true;
    g.mesh.boundingSphere = null;  // stale: recomputed by the next ray cast
  }
  if (simTime < lastSimTime) clearTrails();  // reset: the trails would jump
  lastSimTime = simTime;
  addTrailPoints();
  debug.frames += 1;
  debug.lastState = { tick, simTime, bodies: n, generation };
  // Latency: rigidd's publish (its wall clock) to the frame that draws this state (measured
  // when the frame is rendered). Both clocks are this host's CLOCK_REALTIME.
  if (stampNs > 0n) pendingStampMs = Number(stampNs / 1000n) / 1000;
  $('simtime').textContent = `${simTime.toFixed(3)} s`;
  stateChanged = true;
  if (selected && !selectedShown) showSelected();
}

function setStats(s) {
  debug.stats = s;
  $('rtf').textContent = s.rtf === null ? '–' : s.rtf.toFixed(3) + (s.paused ? ' (paused)' : '');
  $('lateness').textContent = s.lateness_p99_us === null ? '–' : `${s.lateness_p99_us.toFixed(1)} µs`;
  $('overruns').textContent = String(s.overruns);
  $('refused').textContent = String(s.refused);
  $('frozen').textContent = Number.isInteger(s.frozen) ? String(s.frozen) : '–';
  if (Number.isFinite(s.lateness_p99_us)) latenessChart.push(performance.now() / 1000, [s.lateness_p99_us]);
}

function showAnswer(text, ok) {
  const a = $('answer');
  a.textContent = text;
  a.className = ok ? '' : 'bad';
}

// The connection to rigid-view (reconnects when it goes away).
let socket = null;
// The newest state frame received and not applied yet ({ data, receivedAt, receivedWall }, from
// the socket): the next animation frame applies it at its start. rigid-view keeps several states
// in flight (server.hpp, kMaxUnackedStates), so that a state published just before a frame can be
// there for it; when more than one comes between two frames only the newest is decoded, and
// every one is acknowledged when that frame is drawn.
let newestState = null;
debug.statesReceived = 0;  // state frames received, and those a newer one replaced unapplied
debug.statesSkipped = 0;

function applyNewestState() {
  if (!newestState) return;
  const s = newestState;
  newestState = null;
  const t0 = performance.now();
  try {
    applyState(s.data);
  } catch (e) {
    // Reported as uncaught, but not thrown: out of the animation frame, it would end three.js's
    // animation loop.
    reportError(e);
    return;
  }
  arrival = { wall: s.receivedWall, worker: s.receivedAt, main: performance.timeOrigin + t0 };
  debug.stateMs += performance.now() - t0;
}
let nextId = 1;
function connect() {
  // (Received on a Worker's thread: large state frames arrive whole, worker_socket.js.)
  socket = new WorkerSocket(`ws://${location.host}/ws`);
  socket.onopen = () => {
    statesToAck = 0;  // a new connection: nothing is owed
    newestState = null;
    debug.connected = true;
    $('status').textContent = 'connected';
    $('status').className = '';
  };
  socket.onclose = () => {
    debug.connected = false;
    $('status').textContent = 'disconnected from rigid-view: retrying…';
    $('status').className = 'bad';
    setTimeout(connect, 1000);
  };
  socket.onmessage = (event) => {
    ensureLoop();
    if (event.data instanceof ArrayBuffer) {
      debug.statesReceived += 1;
      if (newestState) debug.statesSkipped += 1;
      newestState = event;
      statesToAck += 1;
      return;
    }
    const msg = JSON.parse(event.data);
    switch (msg.type) {
      case 'hello':
        debug.readOnly = msg.read_only;
        debug.connection = msg.connection;
        for (const id of ['pause', 'resume', 'step', 'reset']) $(id).disabled = msg.read_only;
        if (msg.read_only) showAnswer('read-only: rigid-view refuses commands', true);
        // Playback (rigid-view FILE): the timeline instead of rigidd's controls.
        debug.mode = msg.mode || 'live';
        $('controls').hidden = debug.mode === 'playback';
        if (debug.mode === 'playback') timeline.show(msg.read_only);
        break;
      case 'scene':
        newestState = null;  // the old scene's (still acknowledged with the next frame)
        setScene(msg);
        break;
      case 'stats': setStats(msg); break;
      case 'wrenches': setWrenches(msg); break;
      case 'playback': debug.playback = msg; timeline.update(msg); break;
      case 'reply':
        debug.replies.push(msg);
        if (debug.replies.length > 100) debug.replies.shift();
        showAnswer(msg.ok ? `${msg.op}: ok at tick ${msg.tick}`
                          : `${msg.op}: ${msg.outcome}: ${msg.message}`, msg.ok);
        break;
      case 'error':
        debug.errors.push(msg.message);
        if (debug.errors.length > 100) debug.errors.shift();
        showAnswer(`refused by rigid-view: ${msg.message}`, false);
        break;
      default: break;
    }
  };
}

function send(command) {
  if (!socket || socket.readyState !== WebSocket.OPEN) {
    showAnswer('not connected', false);
    return null;
  }
  socket.send(JSON.stringify(command));
  return command.id;
}
function control(op, extra = {}) {
  const id = nextId++;
  showAnswer(`${op}: waiting for ${debug.mode === 'playback' ? 'rigid-view' : 'rigidd'}…`, true);
  return send({ op, id, ...extra });
}
$('pause').onclick = () => control('pause');
$('resume').onclick = () => control('resume');
$('reset').onclick = () => control('reset');
$('steps').max = String(kMaxSteps);
$('step').onclick = () => {
  const steps = Number($('steps').value);
  if (!Number.isInteger(steps) || steps < 1 || steps > kMaxSteps) {
    showAnswer(`step: N must be an integer in [1, ${kMaxSteps}]`, false);
    return;
  }
  control('step', { steps });
};
debug.control = control;
// Playback (rigid-view FILE): play, pause, seek and speed; window.rigidView.playback is the last
// "playback" message (where the timeline is).
debug.mode = 'live';
debug.playback = null;
const timeline = createTimeline(control);

// Push: press the left button on a body and drag; while held, a force pulls the picked point
// towards the pointer's spot on the plane through it facing the camera (re-sent each frame with a
// short ttl, so it stops when the button is released).
const raycaster = new THREE.Raycaster();
const pointer = new THREE.Vector2();
let grab = null;  // { id, body, local (from the CoM, in B), plane, target }
// The body under the pointer (raycaster already set) and the hit point in W, or null.
function pick() {
  if (impostors) return pickBodies(raycaster.ray, bodyList);
  const hit = raycaster.intersectObjects(instanced.map((g) => g.mesh), false)
    .find((h) => h.instanceId !== undefined);
  if (!hit) return null;
  const g = instanced.find((x) => x.mesh === hit.object);
  const body = g ? bodies.get(g.ids[hit.instanceId]) : null;
  return body && body.placed ? { body, point: hit.point } : null;
}
const kPushGain = 20;  // N per m of drag
const kMaxPush = 200;  // N
function setPointer(event) {
  const r = renderer.domElement.getBoundingClientRect();
  pointer.set(((event.clientX - r.left) / r.width) * 2 - 1, -((event.clientY - r.top) / r.height) * 2 + 1);
  raycaster.setFromCamera(pointer, camera);
}
// (On the canvas's container: the canvas is replaced when multisampling changes.)
let clicked = null;  // { body, x, y }: a press on a body; released in place, it selects the body
$('view').addEventListener('pointerdown', (event) => {
  if (event.button !== 0) return;
  setPointer(event);
  const b = pick();
  clicked = b ? { body: b.body, x: event.clientX, y: event.clientY } : null;
  if (!b || debug.readOnly || debug.mode === 'playback') return;  // (selects, never pushes)
  const { body, point } = b;
  // The picked point from the CoM, in B: R_WB^T (p_WP - p_WBo).
  const local = point.clone().sub(body.p).applyQuaternion(body.q.clone().invert());
  const normal = camera.getWorldDirection(new THREE.Vector3());
  grab = { id: body.id, body, local,
           plane: new THREE.Plane().setFromNormalAndCoplanarPoint(normal, point),
           target: point.clone() };
  controls.enabled = false;
  renderer.domElement.setPointerCapture(event.pointerId);
});
$('view').addEventListener('pointermove', (event) => {
  setPointer(event);
  if (!grab) {
    hoverPending = true;  // picked once per frame, not per event
    return;
  }
  raycaster.ray.intersectPlane(grab.plane, grab.target);
});
const release = () => { grab = null; controls.enabled = true; grabLine.visible = false; };
$('view').addEventListener('pointerup', (event) => {
  // A click without a drag selects the body.
  if (clicked && Math.hypot(event.clientX - clicked.x, event.clientY - clicked.y) < 4) select(clicked.body);
  clicked = null;
  release();
});
$('view').addEventListener('pointercancel', release);
function sendPush() {
  if (!grab || !socket || socket.readyState !== WebSocket.OPEN) return;
  wake();  // the pull's line follows the body
  // The picked point in W: p_WBo + R_WB p_BoP.
  const at = grab.local.clone().applyQuaternion(grab.body.q).add(grab.body.p);
  const f = grab.target.clone().sub(at).multiplyScalar(kPushGain);
  if (f.length() > kMaxPush) f.setLength(kMaxPush);
  grabLine.geometry.setFromPoints([at, grab.target]);
  grabLine.visible = true;
  socket.send(JSON.stringify({ op: 'push', body: grab.id, force: [f.x, f.y, f.z],
                               point: [grab.local.x, grab.local.y, grab.local.z] }));
  debug.pushes += 1;
}

// The pull: a line from the picked point to the pointer's spot.
const grabLine = new THREE.Line(new THREE.BufferGeometry(),
                                new THREE.LineBasicMaterial({ color: 0xffffff }));
grabLine.visible = false;
grabLine.frustumCulled = false;
scene.add(grabLine);

// Wrench arrows: one per wrench rigidd accepted that still acts (rigid-view forwards the newest
// per source, body and key, at most kMaxWrenchesShown, 20 times a second; in playback the
// recorded ones acting on the state shown), at its application point, along its force,
// kArrowMetresPerNewton long; and for its torque, a circular arrow about the torque's axis
// through the body's origin (torqueArcs, below).
const kMaxArrows = kMaxWrenchesShown;
const kArrowMetresPerNewton = 0.01;
let wrenches = [];
let sceneDt = 0;
const arrows = [];
const isVec3 = (a) => Array.isArray(a) && a.length === 3 && a.every(Number.isFinite);
function setWrenches(msg) {
  if (!Array.isArray(msg.wrenches)) return;
  if (wrenches.length || msg.wrenches.length) wake();
  wrenches = msg.wrenches.slice(-kMaxArrows).filter((w) => w && Number.isInteger(w.body) &&
    Number.isFinite(w.tick) && Number.isFinite(w.ttl) && isVec3(w.force) && isVec3(w.point) &&
    (w.torque === undefined || isVec3(w.torque)));
}
// rigidd's ticks_to_live (server/loop/wrench_table.cpp): the ticks a wrench acts for, ttl / dt
// rounded up (a ratio within 1e-9 of an integer counts as that integer), at least 1.
function ticksToLive(ttl, dt) {
  const ratio = ttl / dt, nearest = Math.round(ratio);
  const ticks = Math.abs(ratio - nearest) <= 1e-9 * Math.max(1, nearest) ? nearest : Math.ceil(ratio);
  return Math.max(1, ticks);
}
// Accepted at tick k, a wrench acts on the steps k -> k+1 ... k+n-1 -> k+n: it is drawn with the
// states those steps produced, k < tick <= k + n, and not past `until` (playback: replaced by a
// newer wrench with its key, or cleared by a reset). Force and torque arrows alike.
function acting(w, tick) {
  if (tick <= w.tick) return false;
  if (Number.isInteger(w.until) && tick > w.until) return false;
  return !(sceneDt > 0) || tick <= w.tick + ticksToLive(w.ttl, sceneDt);
}
function updateArrows() {
  const tick = debug.lastState ? debug.lastState.tick : -Infinity;
  const drawn = [];
  const twisted = [];
  for (const w of wrenches) {
    const b = bodies.get(w.body);
    if (!b || !b.placed || !acting(w, tick)) continue;
    if (w.torque) torqueArcs.draw(w, b, twisted);
    // Application point in W: p_WBo + R_WB p_BoP; the force in W (R_WB f_B when given in B).
    const from = new THREE.Vector3(...w.point).applyQuaternion(b.q).add(b.p);
    const f = new THREE.Vector3(...w.force);
    if (w.force_frame === 'body') f.applyQuaternion(b.q);
    const newtons = f.length();
    if (!(newtons > 1e-9)) continue;
    const k = drawn.length;
    if (!arrows[k]) {
      arrows[k] = new THREE.ArrowHelper(new THREE.Vector3(1, 0, 0), new THREE.Vector3(), 1, 0xffd54f);
      scene.add(arrows[k]);
    }
    const length = Math.min(Math.max(newtons * kArrowMetresPerNewton, 0.05), 3);
    arrows[k].position.copy(from);
    arrows[k].setDirection(f.clone().divideScalar(newtons));
    arrows[k].setLength(length, Math.min(0.2 * length, 0.15), Math.min(0.1 * length, 0.08));
    arrows[k].visible = true;
    drawn.push({ body: w.body, from: from.toArray(), force: f.toArray() });
  }
  for (let k = drawn.length; k < arrows.length; ++k) arrows[k].visible = false;
  torqueArcs.hideFrom(twisted.length);
  debug.arrows = drawn;
  debug.torques = twisted;
}

// Torque arrows: for a wrench's torque tau (N m; in W, or R_WB tau_B when given in B), an arc of
// 270 degrees in the plane through p_WBo perpendicular to tau, ending in a cone: the arc turns
// about tau by the right-hand rule (counter-clockwise seen from the tip of tau). Its radius is the
// body's (its bounding sphere about Bo) plus a margin, so it stays outside the body; its size
// says nothing of |tau| (a torque has no point to scale from). One unit arc about z (three.js's
// TorusGeometry: from +x counter-clockwise, here to -y, where the cone points along +x, the arc's
// tangent there), posed per torque: z -> the axis, scaled by the radius.
const kTorqueColor = 0x64ffda;  // not the force arrows' amber, nor a body's colour (palette)
const kTorqueArc = 1.5 * Math.PI;
const torqueArcs = {
  pool: [],
  unit: null,
  make() {
    if (!this.unit) {
      const material = new THREE.MeshBasicMaterial({ color: kTorqueColor });
      const cone = new THREE.ConeGeometry(0.09, 0.3, 12);  // along +y, centred
      cone.rotateZ(-Math.PI / 2);                           // along +x
      cone.translate(0.15, -1, 0);                          // its base on the arc's end, (0, -1, 0)
      this.unit = { arc: new THREE.TorusGeometry(1, 0.025, 6, 36, kTorqueArc), cone, material };
    }
    const group = new THREE.Group();
    group.add(new THREE.Mesh(this.unit.arc, this.unit.material));
    group.add(new THREE.Mesh(this.unit.cone, this.unit.material));
    scene.add(group);
    return group;
  },
  // Draws w's torque on body b (if not zero) and adds what is drawn to `out`.
  draw(w, b, out) {
    const tau = new THREE.Vector3(...w.torque);
    if (w.torque_frame === 'body') tau.applyQuaternion(b.q);  // tau_W = R_WB tau_B
    const size = tau.length();
    if (!(size > 1e-12) || out.length >= kMaxArrows) return;
    const k = out.length;
    const g = this.pool[k] || (this.pool[k] = this.make());
    const axis = tau.clone().divideScalar(size);
    const radius = Math.max(1.3 * b.radius, 0.1);
    g.position.copy(b.p);
    g.quaternion.setFromUnitVectors(new THREE.Vector3(0, 0, 1), axis);
    g.scale.setScalar(radius);
    g.visible = true;
    g.updateMatrix();
    // Where the cone is and where it points, from the pose given to three.js (what is drawn).
    const tip = new THREE.Vector3(0, -1, 0).applyMatrix4(g.matrix);
    const tipDirection = new THREE.Vector3(1, 0, 0).applyQuaternion(g.quaternion);
    out.push({ body: w.body, center: b.p.toArray(), torque: tau.toArray(), axis: axis.toArray(),
               radius, tip: tip.toArray(), tipDirection: tipDirection.toArray() });
  },
  hideFrom(k) {
    for (; k < this.pool.length; ++k) this.pool[k].visible = false;
  },
};

// Hover: the body's axes (x red, y green, z blue: B), sized to the body.
let hovered = null;
let hoverPending = false;
const hoverAxes = new THREE.AxesHelper(1);
hoverAxes.visible = false;
scene.add(hoverAxes);
function updateHover() {
  if (hoverPending) {
    hoverPending = false;
    const h = pick();
    hovered = h ? h.body : null;
  }
  const b = hovered && hovered.placed ? hovered : null;
  hoverAxes.visible = !!b;
  if (!b) return;
  hoverAxes.position.copy(b.p);
  hoverAxes.quaternion.copy(b.q);
  hoverAxes.scale.setScalar(Math.max(1.6 * b.radius, 0.05));
}

// Trails: the last kTrailPoints positions of at most kMaxTrails bodies (the selected one, the
// hovered one, then the first in scene order), each a fixed-size buffer; off unless ticked.
const kMaxTrails = 16;
const kTrailPoints = 256;
const trails = new Map();  // id -> { line, xyz: Float32Array, count }
function clearTrails() {
  for (const t of trails.values()) {
    scene.remove(t.line);
    t.line.geometry.dispose();
    t.line.material.dispose();
  }
  trails.clear();
}
function trailBodies() {
  const out = new Set();
  if (!$('trails').checked) return out;
  for (const b of [selected, hovered]) if (b) out.add(b);
  for (let i = 0; i < bodyList.length && out.size < kMaxTrails; ++i) out.add(bodyList[i]);
  return out;
}
function addTrailPoints() {
  const want = trailBodies();
  for (const [id, t] of trails) {
    if (![...want].some((b) => b.id === id)) {
      scene.remove(t.line);
      t.line.geometry.dispose();
      t.line.material.dispose();
      trails.delete(id);
    }
  }
  for (const b of want) {
    if (!b.placed) continue;
    let t = trails.get(b.id);
    if (!t) {
      const xyz = new Float32Array(3 * kTrailPoints);
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute('position', new THREE.BufferAttribute(xyz, 3).setUsage(THREE.DynamicDrawUsage));
      const line = new THREE.Line(geometry, new THREE.LineBasicMaterial({
        color: palette[b.index % palette.length], transparent: true, opacity: 0.7 }));
      line.frustumCulled = false;
      scene.add(line);
      t = { line, xyz, count: 0 };
      trails.set(b.id, t);
    }
    if (t.count === kTrailPoints) t.xyz.copyWithin(0, 3);  // full: drop the oldest
    else t.count += 1;
    t.xyz.set([b.p.x, b.p.y, b.p.z], 3 * (t.count - 1));
    t.line.geometry.attributes.position.needsUpdate = true;
    t.line.geometry.setDrawRange(0, t.count);
  }
  debug.trails = trails.size;
}
$('trails').onchange = () => { if (!$('trails').checked) clearTrails(); };

// The body list (search by name or id; the first kMaxListed matches) and the selected body.
const kMaxListed = 200;
let selected = null;
function fillBodyList() {
  const query = $('search').value.trim().toLowerCase();
  const list = $('bodylist');
  list.replaceChildren();
  let matches = 0;
  for (const b of bodyList) {
    if (query && !b.name.toLowerCase().includes(query) && String(b.id) !== query) continue;
    if (++matches > kMaxListed) continue;
    const row = document.createElement('div');
    row.textContent = `${b.id} ${b.name}`;
    row.className = b === selected ? 'row sel' : 'row';
    row.onclick = () => select(b === selected ? null : b);
    list.appendChild(row);
  }
  $('listcount').textContent = matches > kMaxListed ? `${kMaxListed} of ${matches}` : `${matches}`;
}
$('search').oninput = fillBodyList;
function select(b) {
  wake();  // (trails, follow; a click on the body list wakes too)
  selected = b;
  selectedShown = false;
  watchSelected();
  debug.selected = b ? b.name : null;
  $('selected').style.display = b ? '' : 'none';
  if (b) $('selname').textContent = `${b.name} (id ${b.id}, ${b.shape}, ${+b.mass.toPrecision(4)} kg)`;
  fillBodyList();
  driftChart.clear();  // a different quantity from here on
}
// Large live scenes: rigid-view sends the selected body's whole state ("watch", protocol.hpp),
// asked for again every kWatchEvery ms (a reconnected page gets the scene again, which clears the
// selection).
function watchSelected() {
  if (!socket || socket.readyState !== WebSocket.OPEN || debug.mode === 'playback') return;
  socket.send(JSON.stringify(selected ? { op: 'watch', body: selected.id } : { op: 'watch' }));
}
setInterval(() => { if (selected) watchSelected(); }, kWatchEvery);
const fmt = (a) => a.map((x) => (Math.abs(x) < 1e-12 ? '0' : x.toPrecision(4))).join(', ');
// The panel follows the plots' 10 samples a second, but a body just selected is shown with the
// first state that has all of it (selectedShown), not up to a sample later.
let selectedShown = false;
function showSelected() {
  const b = selected;
  if (!b || !b.placed) return;
  $('selp').textContent = fmt(b.p.toArray());
  $('selq').textContent = fmt([b.q.w, b.q.x, b.q.y, b.q.z]);
  $('selv').textContent = b.moving ? fmt(b.v.toArray()) : '–';
  $('selw').textContent = b.moving ? fmt(b.w.toArray()) : '–';
  selectedShown = b.moving;
}
// "Follow": the camera keeps its offset from the selected body.
function follow() {
  if (!selected || !selected.placed || !$('follow').checked) return;
  const delta = selected.p.clone().sub(controls.target);
  controls.target.add(delta);
  camera.position.add(delta);
}

// Plots: relative drift of energy and angular momentum (rigid-view's, drift.js) of the selected
// body, or the largest over all bodies, 10 samples a second; tick lateness p99 from each Stats
// report.
const drift = new DriftTable();
let slots = new Int32Array(0);  // state slot -> scene index
let lastSimTime = -Infinity;
let stateChanged = false;
const driftChart = new StripChart($('plot-drift'), {
  series: [{ name: 'energy', color: '#4fc3f7' }, { name: 'ang. momentum', color: '#ffb74d' }],
  log: true });
const latenessChart = new StripChart($('plot-lateness'), {
  series: [{ name: 'tick lateness p99', color: '#81c784' }], unit: ' µs' });
let nextSample = 0;
// "all bodies (max: craft)": the worst body is named, so that a body the scene pushes (whose
// energy changes by the work done on it) is seen for what it is; click a body for its own drift.
function worstLabel(d) {
  const name = (i) => (i >= 0 && i < bodyList.length ? bodyList[i].name : null);
  const e = name(d.energyAt), m = name(d.momentumAt);
  if (!e && !m) return 'all bodies (max)';
  return `all bodies (max: ${e === m || !m ? e : !e ? m : `${e}, ${m}`})`;
}
function samplePlots(now) {
  if (now < nextSample) return;
  nextSample = now + 100;
  if (stateChanged) {
    stateChanged = false;
    const d = drift.worst(selected ? selected.index : -1);
    driftChart.push(now / 1000, [d.energy, d.momentum]);
    $('plot-of').textContent = selected ? selected.name : worstLabel(d);
    showSelected();
  }
  driftChart.draw();
  latenessChart.draw();
}

// The last 4096 latencies (ms) from rigidd's publish to the rendered frame (bench/view), and
// their parts: publish to the worker's receipt (rigidd, the bus, rigid-view, the WebSocket), on
// to the main thread applying it (the hand-over, then the wait for the next frame's start), on to
// the end of that frame (renders it).
let pendingStampMs = null;
// Wall clock (Date.now(), ms) of the last state's receipt on the worker, and the performance
// clock (timeOrigin + now) there and on the main thread: { wall, worker, main } (worker_socket.js).
let arrival = null;
let statesToAck = 0;  // state frames received and not yet drawn
const latencies = new Float64Array(4096);
const latencyParts = { toWorker: new Float64Array(4096), toMain: new Float64Array(4096),
                       toFrame: new Float64Array(4096) };
let latencyCount = 0;
// Frames drawn, and frames not drawn since nothing changed: redraw.js counts them.
Object.defineProperty(debug, 'rendered', { get: () => redraw.drawn, enumerable: true });
Object.defineProperty(debug, 'skipped', { get: () => redraw.skipped, enumerable: true });
debug.unacknowledged = () => statesToAck;  // states received and not yet acknowledged
// Redraws of the plots' canvases (they too draw only on change).
debug.plotDraws = () => ({ drift: driftChart.drawn, lateness: latenessChart.drawn });
debug.renderMs = 0;  // total time in renderer.render, and in applying states (bench/view)
debug.stateMs = 0;
debug.latencies = () => Array.from(latencies.subarray(0, Math.min(latencyCount, latencies.length)));
debug.latencyParts = () => Object.fromEntries(Object.entries(latencyParts).map(
  ([k, a]) => [k, Array.from(a.subarray(0, Math.min(latencyCount, a.length)))]));
debug.clearLatencies = () => { latencyCount = 0; };

function resize() {
  wake();
  const w = window.innerWidth, h = window.innerHeight;
  renderer.setSize(w, h);
  camera.aspect = w / Math.max(h, 1);
  camera.updateProjectionMatrix();
}
window.addEventListener('resize', resize);
resize();
// Dynamic resolution (render_scale.js): one decision per second of frames, only while the page is
// shown (a hidden page gets no frames to count).
function setRenderScale(scale) {
  if (scale === renderScale) return;
  renderScale = scale;
  renderer.setPixelRatio(window.devicePixelRatio * renderScale);
  resize();
}
function adaptRenderScale(now, drawn) {
  // (Frames not drawn (redraw.js) say nothing of what drawing costs: the window starts again.)
  const judged = document.visibilityState === 'visible' && !renderScaleHeld && drawn;
  const scale = renderScaleControl.frame(now, judged);
  if (!renderScaleHeld) setRenderScale(scale);
}
debug.renderScale = () => renderScale;
// holdRenderScale(scale): render at that scale until holdRenderScale(null) hands it back.
debug.holdRenderScale = (scale) => {
  if (scale === null) {
    renderScaleHeld = false;
    setRenderScale(renderScaleControl.scale);
    return;
  }
  if (!(scale > 0 && scale <= 1)) throw new RangeError(`holdRenderScale: expected a scale in (0, 1] or null, got ${scale}`);
  renderScaleHeld = true;
  setRenderScale(scale);
  wake();  // (a frame at the held scale, even if it was the scale already)
};
// The controller's decisions so far (bench/view): lowered, raised, failed probes, and the current
// wait before a probe (s).
debug.renderScaleDecisions = () => ({ lowered: renderScaleControl.lowered, raised: renderScaleControl.raised,
                                      failedProbes: renderScaleControl.failedProbes,
                                      raiseAfter: renderScaleControl.raiseAfter });

// The drawn frames' timestamps (ms), the last 4096 (bench/view counts the refreshes missed).
const frameTimes = new Float64Array(4096);
let frameCount = 0;
debug.frameTimes = () => {
  const n = Math.min(frameCount, frameTimes.length), first = frameCount - n;
  return Array.from({ length: n }, (_, i) => frameTimes[(first + i) % frameTimes.length]);
};

function frame(now) {
  applyNewestState();
  sendPush();
  updateHover();
  updateArrows();
  follow();
  samplePlots(now);
  if (controls.update()) wake();  // (true while the camera moves, damping included)
  const draw = redraw.due(now);
  adaptRenderScale(now, draw);
  if (draw) {
    frameTimes[frameCount++ % frameTimes.length] = now;
    const t0 = performance.now();
    renderer.render(scene, camera);
    debug.renderMs += performance.now() - t0;  // (the GPU's work may finish later)
  } else {
    pendingStampMs = null;  // a state that changed nothing drawn: no latency to a frame
  }
  // Drawn: rigid-view may send the next states (it keeps at most four unacknowledged), one for
  // each received since the last frame, applied or replaced.
  for (; statesToAck > 0; --statesToAck)
    if (socket && socket.readyState === WebSocket.OPEN) socket.send(kAckCommand);
  if (pendingStampMs !== null) {
    // Against rigidd's stamp, the wall clock now (1 ms steps); within the page, its own clocks.
    const now = performance.timeOrigin + performance.now(), k = latencyCount++ % latencies.length;
    latencies[k] = Date.now() - pendingStampMs;
    const a = arrival && Number.isFinite(arrival.worker) ? arrival : { wall: NaN, worker: NaN, main: NaN };
    latencyParts.toWorker[k] = a.wall - pendingStampMs;
    latencyParts.toMain[k] = a.main - a.worker;
    latencyParts.toFrame[k] = now - a.main;
    pendingStampMs = null;
  }
  // Nothing drawn (and no state waits: messages come between frames, and this one applied the
  // newest): the loop stops until ensureLoop starts it again.
  if (!draw) {
    renderer.setAnimationLoop(null);
    looping = false;
  }
}
ensureLoop();
connect();
