// rigid-view's page: draws rigidd's bodies from the scene message and the binary state frames
// rigid-view sends (protocol.js), shows Stats, sends pause/resume/step/reset, pushes (drag a body)
// and edits (put a body back, set its state), draws the accepted wrenches as arrows, live or
// recorded, a body list with the selected body's state, names, trails, and plots of energy and
// angular-momentum drift and of tick lateness.
//
// This module makes the page's parts and joins them; each part is a module of its own:
//   protocol.js     the state frames decoded (layout generated from protocol.hpp)
//   connection.js   the WebSocket to rigid-view: messages in, commands and acknowledgements out
//   viewport.js     renderer, scene, camera and orbit controls, render scale
//   stage.js        background, grid, world axes, lights, the bodies' octant markings
//   framing.js      zoom to fit (a new scene is framed at its first state)
//   draw_loop.js    the animation loop, drawing only on change (redraw.js)
//   bodies.js       the scene's bodies: built from the scene message, placed by each state
//   static_parts.js the scene's planes and static shapes, drawn once from the scene message
//   shapes.js, impostors.js, impostor_shaders.js   how bodies are drawn (small and large scenes)
//   picking.js      the body under a ray
//   input.js        the pointer: push, select, hover;  push.js: the push itself (a damped spring)
//   labels.js       names: the hovered body's, and all (the "names" switch)
//   body_edit.js    the selected body's edits: put back, stop, set state
//   help.js         the keys, and the overlay listing them with the mouse's gestures
//   selection.js    the selected body and what follows it
//   wrenches.js     accepted wrenches as force and torque arrows
//   trails.js       trails;  hud.js: status, Stats, controls;  panel.js: body list, plots
//   timings.js      the page's own measurements;  debug.js: window.rigidView, for tests and bench
//   timeline.js     playback's timeline (rigid-view FILE)
// A new message type gets its case in onMessage; what a frame does is in frame(), in order.
import { Bodies, isLarge } from './bodies.js';
import { BodyEdit } from './body_edit.js';
import { Connection } from './connection.js';
import { exposeDebug } from './debug.js';
import { DrawLoop } from './draw_loop.js';
import { DriftTable } from './drift.js';
import { Framing } from './framing.js';
import { Keys } from './help.js';
import { Hud } from './hud.js';
import { PointerInput } from './input.js';
import { Labels } from './labels.js';
import { Panel } from './panel.js';
import { decodeState } from './protocol.js';
import { Push } from './push.js';
import { Selection } from './selection.js';
import { StaticParts } from './static_parts.js';
import { createTimeline } from './timeline.js';
import { Timings } from './timings.js';
import { Trails } from './trails.js';
import { Viewport } from './viewport.js';
import { Wrenches } from './wrenches.js';

const wake = () => loop.wake();  // (loop is made below, before anything wakes)
const viewport = new Viewport(document.getElementById('view'), wake);
const loop = new DrawLoop(viewport, frame);
const { scene } = viewport;
const bodies = new Bodies(scene);
const parts = new StaticParts(scene);
const connection = new Connection({ open: () => hud.connected(true), close: () => hud.connected(false),
                                    state: () => loop.ensure(), message: onMessage });
const push = new Push(scene, viewport, connection);
const wrenches = new Wrenches(scene, bodies, viewport.camera);
const selection = new Selection();
const input = new PointerInput(document.getElementById('view'),
                               { viewport, bodies, push, selection, connection });
const trails = new Trails(scene, bodies, () => [selection.body, input.hovered]);
const drift = new DriftTable();
const hud = new Hud(connection);
const panel = new Panel(bodies, selection, viewport, drift);
const timeline = createTimeline((op, extra) => hud.control(op, extra));
const timings = new Timings();
const framing = new Framing(viewport, bodies);
const labels = new Labels(document.getElementById('labels'), viewport, bodies,
                          () => [selection.body, input.hovered]);
const bodyEdit = new BodyEdit(selection, hud);
const $ = (id) => document.getElementById(id);
const toggle = (id) => {
  $(id).checked = !$(id).checked;
  $(id).dispatchEvent(new Event('change'));
};
$('fit').onclick = () => { framing.fit(); wake(); };
$('names').onchange = () => { labels.toggle($('names').checked); wake(); };
const keys = new Keys({
  pauseOrResume: () => hud.control(hud.lastStats && hud.lastStats.paused ? 'resume' : 'pause'),
  step: () => $('step').click(),
  fit: () => { framing.fit(); wake(); },
  names: () => toggle('names'),
  trails: () => toggle('trails'),
  putBack: () => bodyEdit.putBack(),
  deselect: () => selection.set(null),
});
// The scene shown, as window.rigidView describes it: { scene: { name, generation, dt }, bodies:
// [{ id, name, shape, fromMoments }] }.
let shown = { scene: null, bodies: [] };

selection.onChange(() => {
  wake();  // (trails, follow; a click on the body list wakes too)
  connection.watch();
});
// The body pulled, else the one selected: a large scene's pose frames carry their whole state
// (velocities: the push's damping, the body panel).
connection.watched = () => (push.active ? push.grab.id : selection.body ? selection.body.id : null);

function onMessage(msg) {
  loop.ensure();
  switch (msg.type) {
    case 'hello':
      hud.hello(msg.read_only, connection.mode);
      bodyEdit.hello(msg.read_only, connection.mode);
      if (connection.mode === 'playback') timeline.show(msg.read_only);
      break;
    case 'scene': setScene(msg); break;
    case 'stats':
      hud.stats(msg);
      panel.stats(msg);
      break;
    case 'wrenches': if (wrenches.set(msg)) wake(); break;
    case 'playback': timeline.update(msg); break;
    case 'reply': hud.reply(msg); break;
    case 'error': hud.refused(msg.message); break;
    default: break;
  }
}

function setScene(msg) {
  bodies.clear();
  viewport.newScene(isLarge(msg));
  bodies.build(msg);
  parts.build(msg);
  wake();
  drift.setBodies(msg.bodies.length);
  wrenches.newScene(msg);
  selection.set(null);
  input.newScene();
  push.newScene(msg);
  framing.newScene();
  labels.newScene();
  trails.clear();
  panel.newScene();
  shown = { scene: { name: msg.name, generation: msg.generation, dt: msg.dt },
            bodies: msg.bodies.map((b) => ({ id: b.id, name: b.name, shape: b.shape,
                                             fromMoments: !!b.from_moments })) };
  hud.scene(msg);
}

// The newest state frame received, applied at the start of an animation frame.
function applyNewestState() {
  const s = connection.takeState();
  if (!s) return;
  const t0 = performance.now();
  let state;
  try {
    state = decodeState(s.data);
    applyState(state);
  } catch (e) {
    // Reported as uncaught, but not thrown: out of the animation frame, it would end three.js's
    // animation loop.
    reportError(e);
    return;
  }
  timings.stateApplied(s, state.stampNs, t0);
  timings.stateMs += performance.now() - t0;
}

function applyState(state) {
  if (bodies.apply(state)) wake();
  drift.apply(state, bodies.slots);
  // The wrench arrows drawn depend on the tick (acting), as well as on the poses.
  if (wrenches.list.length && (!bodies.lastState || bodies.lastState.tick !== state.tick)) wake();
  bodies.commit(state);
  if (framing.stateApplied()) wake();
  trails.add(state.simTime);
  hud.simTime(state.simTime);
  panel.stateApplied();
}

function frame(now) {
  applyNewestState();
  if (push.send(bodies.lastState ? bodies.lastState.simTime : 0)) wake();  // (the line follows)
  input.updateHover();
  labels.update(input.axes.visible ? input.hovered : null);
  wrenches.update();
  panel.follow();
  panel.sample(now);
  if (viewport.controls.update()) wake();  // (true while the camera moves, damping included)
  const draw = loop.due(now);
  viewport.adaptRenderScale(now, draw);
  if (draw) {
    timings.frameDrawn(now);
    const t0 = performance.now();
    viewport.render();
    timings.renderMs += performance.now() - t0;
  }
  // Drawn or not, the states received since the last frame are acknowledged.
  connection.acknowledge();
  timings.frameEnded(draw);
  // Nothing drawn (and no state waits: messages come between frames, and this one applied the
  // newest): the loop stops until something starts it again.
  if (!draw) loop.stop();
}

exposeDebug({ viewport, loop, bodies, connection, push, wrenches, selection, input, trails, drift,
               hud, panel, timings, framing, labels, keys, bodyEdit, shown: () => shown,
               staticParts: parts });
viewport.resize();
loop.ensure();
connection.connect();
