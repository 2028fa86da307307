// Edits of the selected body (rigidd's edits, answered like the controls; the answer shows in the
// HUD): "put back" (reset_body: its scene state, the wrenches on it dropped), "stop" (its
// velocities set to zero), and "set state": the position and velocities typed in (x, y, z in the
// world frame; a field left empty is not set), filled with the body's state when opened or on
// "current".
const $ = (id) => document.getElementById(id);
const kFields = [['edit-p', 'position'], ['edit-v', 'velocity'], ['edit-w', 'angular_velocity']];

// Three finite numbers from "x, y, z" (commas or spaces between), or null.
export function parseVector(text) {
  const parts = text.trim().split(/[\s,]+/).filter((x) => x !== '');
  if (parts.length !== 3) return null;
  const v = parts.map(Number);
  return v.every(Number.isFinite) ? v : null;
}

export class BodyEdit {
  // selection (selection.js), hud (hud.js: sends the command and shows its answer).
  constructor(selection, hud) {
    this.selection = selection;
    this.hud = hud;
    $('putback').onclick = () => this.putBack();
    $('stop').onclick = () => this.send('set_state', { velocity: [0, 0, 0], angular_velocity: [0, 0, 0] });
    $('edit-set').onclick = () => this.set();
    $('edit-load').onclick = () => this.load();
    $('setstate').addEventListener('toggle', () => { if ($('setstate').open) this.load(); });
    selection.onChange(() => { if ($('setstate').open) this.load(); });
  }

  // hello: no edits from a read-only page, nor in playback (no rigidd to edit).
  hello(readOnly, mode) {
    $('edit').hidden = readOnly || mode === 'playback';
  }

  // The selected body back to its scene state; its command's id, or null (none selected).
  putBack() {
    return this.send('reset_body', {});
  }

  send(op, extra) {
    const b = this.selection.body;
    if (!b) return null;
    return this.hud.control(op, { body: b.id, ...extra });
  }

  // The fields filled with the selected body's state (velocities: when the page has them).
  load() {
    const b = this.selection.body;
    if (!b || !b.placed) return;
    const text = (v) => v.map((x) => +x.toPrecision(6)).join(', ');
    $('edit-p').value = text(b.p.toArray());
    $('edit-v').value = b.moving ? text(b.v.toArray()) : '';
    $('edit-w').value = b.moving ? text(b.w.toArray()) : '';
  }

  // set_state with the fields given; its command's id, or null (nothing to send, or a field that
  // is not three numbers: said in the HUD).
  set() {
    const extra = {};
    for (const [id, key] of kFields) {
      const text = $(id).value;
      if (text.trim() === '') continue;
      const v = parseVector(text);
      if (!v) {
        this.hud.answer(`set_state: ${key} must be three numbers x, y, z, got '${text}'`, false);
        return null;
      }
      extra[key] = v;
    }
    if (Object.keys(extra).length === 0) {
      this.hud.answer('set_state: nothing to set (position, velocity, angular velocity)', false);
      return null;
    }
    return this.send('set_state', extra);
  }
}
