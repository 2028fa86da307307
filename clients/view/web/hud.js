// The HUD (index.html's #hud, top left): the connection's status, the scene, rigidd's Stats, the
// controls (pause, resume, step N, reset) and the answer to the last command.
import { kMaxSteps } from './protocol.js';

const $ = (id) => document.getElementById(id);

export class Hud {
  // connection: connection.js's, through which the controls go.
  constructor(connection) {
    this.connection = connection;
    this.lastStats = null;
    $('steps').max = String(kMaxSteps);
    $('pause').onclick = () => this.control('pause');
    $('resume').onclick = () => this.control('resume');
    $('reset').onclick = () => this.control('reset');
    $('step').onclick = () => {
      const steps = Number($('steps').value);
      if (!Number.isInteger(steps) || steps < 1 || steps > kMaxSteps) {
        this.answer(`step: N must be an integer in [1, ${kMaxSteps}]`, false);
        return;
      }
      this.control('step', { steps });
    };
  }

  // Sends a command with a fresh id (the controls, the playback timeline; window.rigidView): its
  // id, or null when not connected. The answer shows when it comes.
  control(op, extra = {}) {
    this.answer(`${op}: waiting for ${this.connection.mode === 'playback' ? 'rigid-view' : 'rigidd'}…`, true);
    const id = this.connection.command(op, extra);
    if (id === null) this.answer('not connected', false);
    return id;
  }

  answer(text, ok) {
    const a = $('answer');
    a.textContent = text;
    a.className = ok ? '' : 'bad';
  }

  connected(yes) {
    $('status').textContent = yes ? 'connected' : 'disconnected from rigid-view: retrying…';
    $('status').className = yes ? '' : 'bad';
  }

  // hello: read-only pages offer no controls; playback (rigid-view FILE) shows its timeline
  // instead of rigidd's controls.
  hello(readOnly, mode) {
    for (const id of ['pause', 'resume', 'step', 'reset']) $(id).disabled = readOnly;
    if (readOnly) this.answer('read-only: rigid-view refuses commands', true);
    $('controls').hidden = mode === 'playback';
  }

  // An answer from rigid-view: a command's reply, or a refused frame.
  reply(msg) {
    this.answer(msg.ok ? `${msg.op}: ok at tick ${msg.tick}` : `${msg.op}: ${msg.outcome}: ${msg.message}`, msg.ok);
  }

  refused(message) {
    this.answer(`refused by rigid-view: ${message}`, false);
  }

  scene(msg) {
    $('scene').textContent = `${msg.name || '(unnamed)'} · ${msg.bodies.length} bodies`;
  }

  simTime(t) {
    $('simtime').textContent = `${t.toFixed(3)} s`;
  }

  stats(s) {
    this.lastStats = s;
    $('rtf').textContent = s.rtf === null ? '–' : s.rtf.toFixed(3) + (s.paused ? ' (paused)' : '');
    $('lateness').textContent = s.lateness_p99_us === null ? '–' : `${s.lateness_p99_us.toFixed(1)} µs`;
    $('overruns').textContent = String(s.overruns);
    $('refused').textContent = String(s.refused);
    $('frozen').textContent = Number.isInteger(s.frozen) ? String(s.frozen) : '–';
  }
}
