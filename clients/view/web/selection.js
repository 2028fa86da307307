// The selected body (a click on it or on its row in the body list; none at first and after a new
// scene), and what follows it: the side panel shows its state and drift, rigid-view is asked for
// its whole state, the camera may follow it, its trail is kept. Each of those registers with
// onChange.
export class Selection {
  constructor() {
    this.body = null;  // a body of bodies.js, or null
    this.listeners = [];
  }

  // listener(body): called with the new selection (or null) each time it is set.
  onChange(listener) {
    this.listeners.push(listener);
  }

  set(body) {
    this.body = body;
    for (const listener of this.listeners) listener(body);
  }
}
