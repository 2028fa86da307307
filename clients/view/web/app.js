// rigid-view's page: draws rigidd's bodies from SceneInfo and the binary state frames rigid-view
// sends (protocol.hpp), shows Stats, sends pause/resume/step/reset and pushes (drag a body).
// window.rigidView exposes what is drawn, for tests and for the console.
import * as THREE from 'three';
import { OrbitControls } from '/three/OrbitControls.js';

const kMagic = 0x31565752;
const $ = (id) => document.getElementById(id);

const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio);
$('view').appendChild(renderer.domElement);
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

const bodies = new Map();  // id -> { id, name, shape, mesh }
const bodyGroup = new THREE.Group();
scene.add(bodyGroup);

const debug = {
  connected: false, readOnly: false, connection: 0, scene: null, bodies: [], stats: null,
  frames: 0, lastState: null, replies: [], errors: [], pushes: 0,
  // The pose drawn for a body: position and orientation (w, x, y, z), and the tick it came from.
  renderedPose(name) {
    for (const b of bodies.values()) {
      if (b.name !== name) continue;
      const p = b.mesh.position, q = b.mesh.quaternion;
      return { tick: debug.lastState ? debug.lastState.tick : -1,
               position: [p.x, p.y, p.z], orientation: [q.w, q.x, q.y, q.z] };
    }
    return null;
  },
};
window.rigidView = debug;

const palette = [0x4fc3f7, 0xffb74d, 0x81c784, 0xe57373, 0xba68c8, 0xfff176, 0x90a4ae];

function geometryOf(b) {
  const d = b.dims || [0.1, 0.1, 0.1];
  const positive = (v, fallback) => (Number.isFinite(v) && v > 0 ? v : fallback);
  let g;
  switch (b.shape) {
    case 'sphere': g = new THREE.SphereGeometry(positive(d[0], 0.05), 32, 16); break;
    case 'cylinder':
      g = new THREE.CylinderGeometry(positive(d[0], 0.05), positive(d[0], 0.05), positive(d[1], 0.1), 32);
      g.rotateX(Math.PI / 2);  // three's axis is y, rigid's is z
      break;
    case 'capsule':
      g = new THREE.CapsuleGeometry(positive(d[0], 0.05), positive(d[1], 0.1), 8, 24);
      g.rotateX(Math.PI / 2);
      break;
    case 'ellipsoid':
      g = new THREE.SphereGeometry(1, 32, 16);
      g.scale(positive(d[0], 0.05), positive(d[1], 0.05), positive(d[2], 0.05));
      break;
    default:
      g = new THREE.BoxGeometry(positive(d[0], 0.1), positive(d[1], 0.1), positive(d[2], 0.1));
      if (b.frame) {  // the box of a body's principal moments: its axes in B
        const [w, x, y, z] = b.frame;
        g.applyQuaternion(new THREE.Quaternion(x, y, z, w).normalize());
      }
  }
  return g;
}

function setScene(msg) {
  for (const b of bodies.values()) {
    bodyGroup.remove(b.mesh);
    b.mesh.geometry.dispose();
    b.mesh.material.dispose();
  }
  bodies.clear();
  msg.bodies.forEach((b, i) => {
    const material = new THREE.MeshStandardMaterial({
      color: palette[i % palette.length], roughness: 0.6, metalness: 0.1,
      transparent: !!b.from_moments, opacity: b.from_moments ? 0.6 : 1 });
    const mesh = new THREE.Mesh(geometryOf(b), material);
    mesh.userData.bodyId = b.id;
    mesh.visible = false;  // until a state places it
    bodyGroup.add(mesh);
    bodies.set(b.id, { id: b.id, name: b.name, shape: b.shape, mesh });
  });
  debug.scene = { name: msg.name, generation: msg.generation, dt: msg.dt };
  debug.bodies = msg.bodies.map((b) => ({ id: b.id, name: b.name, shape: b.shape,
                                          fromMoments: !!b.from_moments }));
  $('scene').textContent = `${msg.name || '(unnamed)'} · ${msg.bodies.length} bodies`;
}

function applyState(buffer) {
  if (buffer.byteLength < 32) throw new Error('short state frame');
  const v = new DataView(buffer);
  if (v.getUint32(0, true) !== kMagic) throw new Error('bad state frame');
  const n = v.getUint32(4, true);
  if (buffer.byteLength !== 32 + 60 * n) throw new Error('state frame of the wrong length');
  const generation = v.getUint32(8, true);
  const tick = Number(v.getBigInt64(16, true));
  const simTime = v.getFloat64(24, true);
  const pos = new Float64Array(buffer, 32, 3 * n);
  const ori = new Float64Array(buffer, 32 + 24 * n, 4 * n);
  const ids = new Int32Array(buffer, 32 + 56 * n, n);
  for (let i = 0; i < n; ++i) {
    const b = bodies.get(ids[i]);
    if (!b) continue;
    b.mesh.position.set(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]);
    b.mesh.quaternion.set(ori[4 * i + 1], ori[4 * i + 2], ori[4 * i + 3], ori[4 * i]);
    b.mesh.visible = true;
  }
  debug.frames += 1;
  debug.lastState = { tick, simTime, bodies: n, generation };
  $('simtime').textContent = `${simTime.toFixed(3)} s`;
}

function setStats(s) {
  debug.stats = s;
  $('rtf').textContent = s.rtf === null ? '–' : s.rtf.toFixed(3) + (s.paused ? ' (paused)' : '');
  $('lateness').textContent = s.lateness_p99_us === null ? '–' : `${s.lateness_p99_us.toFixed(1)} µs`;
  $('overruns').textContent = String(s.overruns);
  $('refused').textContent = String(s.refused);
}

function showAnswer(text, ok) {
  const a = $('answer');
  a.textContent = text;
  a.className = ok ? '' : 'bad';
}

// The connection to rigid-view (reconnects when it goes away).
let socket = null;
let nextId = 1;
function connect() {
  socket = new WebSocket(`ws://${location.host}/ws`);
  socket.binaryType = 'arraybuffer';
  socket.onopen = () => {
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
    if (event.data instanceof ArrayBuffer) {
      applyState(event.data);
      return;
    }
    const msg = JSON.parse(event.data);
    switch (msg.type) {
      case 'hello':
        debug.readOnly = msg.read_only;
        debug.connection = msg.connection;
        for (const id of ['pause', 'resume', 'step', 'reset']) $(id).disabled = msg.read_only;
        if (msg.read_only) showAnswer('read-only: rigid-view refuses commands', true);
        break;
      case 'scene': setScene(msg); break;
      case 'stats': setStats(msg); break;
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
  showAnswer(`${op}: waiting for rigidd…`, true);
  return send({ op, id, ...extra });
}
$('pause').onclick = () => control('pause');
$('resume').onclick = () => control('resume');
$('reset').onclick = () => control('reset');
$('step').onclick = () => {
  const steps = Number($('steps').value);
  if (!Number.isInteger(steps) || steps < 1 || steps > 1000000) {
    showAnswer('step: N must be an integer in [1, 1000000]', false);
    return;
  }
  control('step', { steps });
};
debug.control = control;

// Push: press the left button on a body and drag; while held, a force pulls the picked point
// towards the pointer's spot on the plane through it facing the camera (re-sent each frame with a
// short ttl, so it stops when the button is released).
const raycaster = new THREE.Raycaster();
const pointer = new THREE.Vector2();
let grab = null;  // { id, localPoint (from the CoM, in B), plane, target }
const kPushGain = 20;  // N per m of drag
const kMaxPush = 200;  // N
function setPointer(event) {
  const r = renderer.domElement.getBoundingClientRect();
  pointer.set(((event.clientX - r.left) / r.width) * 2 - 1, -((event.clientY - r.top) / r.height) * 2 + 1);
  raycaster.setFromCamera(pointer, camera);
}
renderer.domElement.addEventListener('pointerdown', (event) => {
  if (event.button !== 0 || debug.readOnly) return;
  setPointer(event);
  const hit = raycaster.intersectObjects(bodyGroup.children, false)[0];
  if (!hit) return;
  const mesh = hit.object;
  const local = mesh.worldToLocal(hit.point.clone());
  const normal = camera.getWorldDirection(new THREE.Vector3());
  grab = { id: mesh.userData.bodyId, mesh, local,
           plane: new THREE.Plane().setFromNormalAndCoplanarPoint(normal, hit.point),
           target: hit.point.clone() };
  controls.enabled = false;
  renderer.domElement.setPointerCapture(event.pointerId);
});
renderer.domElement.addEventListener('pointermove', (event) => {
  if (!grab) return;
  setPointer(event);
  raycaster.ray.intersectPlane(grab.plane, grab.target);
});
const release = () => { grab = null; controls.enabled = true; };
renderer.domElement.addEventListener('pointerup', release);
renderer.domElement.addEventListener('pointercancel', release);
function sendPush() {
  if (!grab || !socket || socket.readyState !== WebSocket.OPEN) return;
  const at = grab.mesh.localToWorld(grab.local.clone());
  const f = grab.target.clone().sub(at).multiplyScalar(kPushGain);
  if (f.length() > kMaxPush) f.setLength(kMaxPush);
  socket.send(JSON.stringify({ op: 'push', body: grab.id, force: [f.x, f.y, f.z],
                               point: [grab.local.x, grab.local.y, grab.local.z] }));
  debug.pushes += 1;
}

function resize() {
  const w = window.innerWidth, h = window.innerHeight;
  renderer.setSize(w, h);
  camera.aspect = w / Math.max(h, 1);
  camera.updateProjectionMatrix();
}
window.addEventListener('resize', resize);
resize();
renderer.setAnimationLoop(() => {
  sendPush();
  controls.update();
  renderer.render(scene, camera);
});
connect();
