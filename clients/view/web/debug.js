// window.rigidView: what the page draws and holds, read by the browser tests (tests/view), by
// bench/view and from the console. Every entry reads the part that owns it (app.js lists them);
// nothing here is state of its own.
import * as THREE from 'three';

// parts: the page's parts, as app.js makes them; shown(): the scene shown ({ scene, bodies }).
export function exposeDebug(parts) {
  const { viewport, loop, bodies, connection, push, wrenches, selection, input, trails, drift, hud,
          panel, timings, framing, labels, keys, shown, staticParts } = parts;
  const debug = {
    // The pose drawn for a body: position and orientation (w, x, y, z), and the tick it came from.
    renderedPose: (name) => bodies.renderedPose(name),
    // A body's last published state as the page holds it (velocities in W; null in a large live
    // scene unless the body is selected: pose frames carry the watched bodies' only).
    bodyState: (name) => bodies.stateOf(name),
    // Selects a body by name (as a click on it or its row does), or none; whether it was found.
    select(name) {
      const b = name === null ? null : bodies.find(name);
      if (b === undefined) return false;
      selection.set(b);
      return true;
    },
    // A body's relative drift of energy and angular momentum since its reference state, as
    // rigid-view sends it (clients/view/drift.hpp).
    drift(name) {
      const b = bodies.find(name);
      return b ? drift.worst(b.index) : null;
    },
    // The body that picking finds at a point of the page (CSS pixels), by name, or null.
    bodyAt(x, y) {
      const h = input.bodyAt(x, y);
      return h ? h.body.name : null;
    },
    // The body whose axes are drawn (under the pointer), the followed camera target.
    hovered: () => (input.axes.visible && input.hovered ? input.hovered.name : null),
    target: () => viewport.controls.target.toArray(),
    cameraPosition: () => viewport.camera.position.toArray(),
    // Where a body's centre (plus `offset`, in W) is on the screen, in CSS pixels of the page.
    screenOf(name, offset = [0, 0, 0]) {
      const b = bodies.find(name);
      if (!b || !b.placed) return null;
      return viewport.screenOf(b.p.clone().add(new THREE.Vector3(...offset)));
    },
    // Where a point of the world (W) is on the screen, in CSS pixels of the page.
    screenAt: (p_W) => viewport.screenOf(new THREE.Vector3(...p_W)),
    // Samples the plots received, and the last ones.
    plots: () => ({ drift: panel.driftChart.received, lateness: panel.latenessChart.received,
                    lastDrift: panel.driftChart.last(), lastLateness: panel.latenessChart.last(),
                    of: selection.body ? selection.body.name : 'all (max)' }),
    // How many bodies the meshes draw, how many meshes (draw calls) that takes, and how: 'instanced'
    // (small scenes) or 'impostors'.
    instances: () => bodies.instances(),
    softwareGL: viewport.softwareGL,
    antialias: () => viewport.renderer.getContextAttributes().antialias,
    // Sends a command with a fresh id, as the page's controls do; its id, or null.
    control: (op, extra) => hud.control(op, extra),
    unacknowledged: () => connection.statesToAck,  // states received and not yet acknowledged
    // Redraws of the plots' canvases (they too draw only on change).
    plotDraws: () => ({ drift: panel.driftChart.drawn, lateness: panel.latenessChart.drawn }),
    // The publish-to-frame latencies (ms) and their parts (timings.js), the drawn frames' times.
    latencies: () => timings.latencyList(),
    latencyParts: () => timings.latencyParts(),
    clearLatencies: () => timings.clearLatencies(),
    frameTimes: () => timings.frameTimeList(),
    renderScale: () => viewport.renderScale,
    // Zoom to fit (framing.js): frames the placed bodies now; and the sphere it frames.
    fit: () => framing.fit(),
    // The names shown on the view (labels.js: with "names" on).
    labels: () => labels.shown,
    // holdRenderScale(scale): render at that scale until holdRenderScale(null) hands it back.
    holdRenderScale: (scale) => viewport.holdRenderScale(scale),
    // The controller's decisions so far (bench/view): lowered, raised, failed probes, and the
    // current wait before a probe (s).
    renderScaleDecisions: () => {
      const c = viewport.scaleControl;
      return { lowered: c.lowered, raised: c.raised, failedProbes: c.failedProbes, raiseAfter: c.raiseAfter };
    },
  };
  // Values read where they are kept.
  const values = {
    connected: () => connection.connected,
    readOnly: () => connection.readOnly,
    connection: () => connection.id,
    mode: () => connection.mode,  // 'live', or 'playback' (rigid-view FILE)
    playback: () => connection.playback,  // the last "playback" message (where the timeline is)
    replies: () => connection.replies,
    errors: () => connection.errors,
    statesReceived: () => connection.statesReceived,  // and those a newer one replaced unapplied
    statesSkipped: () => connection.statesSkipped,
    scene: () => shown().scene,
    bodies: () => shown().bodies,
    // The static parts drawn (the scene's planes and static shapes), by name.
    staticParts: () => staticParts.names.slice(),
    stats: () => hud.lastStats,
    frames: () => bodies.statesApplied,  // states applied
    lastState: () => bodies.lastState,   // { tick, simTime, bodies, generation }
    pushes: () => push.sent,
    // The wrench arrows drawn now: [{ body, from (W), force (W), length (m) }].
    arrows: () => wrenches.drawn,
    // The torque arrows drawn now: [{ body, center (p_WBo), torque (W), axis (unit, W), radius,
    // tip (the cone's base on the arc, W), tipDirection (where the cone points, W) }].
    torques: () => wrenches.twisted,
    selected: () => (selection.body ? selection.body.name : null),
    trails: () => trails.count,
    // Frames drawn, and frames not drawn since nothing changed (redraw.js counts them).
    rendered: () => loop.drawn,
    skipped: () => loop.skipped,
    // The hovered body's tooltip (labels.js), or null; whether the help is shown (help.js).
    tooltip: () => (labels.tip.hidden ? null : labels.tip.textContent),
    helpShown: () => keys.shown,
    // The pull's last force (W, N) while a body is dragged (push.js), or null.
    pullForce: () => (push.active ? push.lastForce : null),
    renderMs: () => timings.renderMs,  // total time in renderer.render, and applying states
    stateMs: () => timings.stateMs,
  };
  for (const [name, get] of Object.entries(values)) Object.defineProperty(debug, name, { get, enumerable: true });
  window.rigidView = debug;
  return debug;
}
