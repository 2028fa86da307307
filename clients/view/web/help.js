// The page's keys, and the overlay that lists them with the mouse's gestures (the "?" button, or
// the key ?). Keys act only when no text field has the focus (the search box, step count and the
// state fields take their own keys).
const $ = (id) => document.getElementById(id);

// [keys, what they do], as the overlay lists them; the mouse's gestures first.
const kMouse = [
  ['left drag on a body', 'pull it (a damped spring to the pointer; let go to release it)'],
  ['left drag elsewhere', 'turn the camera about its target'],
  ['right drag', 'move the camera sideways'],
  ['wheel', 'zoom'],
  ['click a body', 'select it (its state, "put back", "set state"); click again or Esc: none'],
  ['hover a body', 'its name and axes'],
];

export class Keys {
  // actions: { pauseOrResume(), fit(), names(), trails(), putBack(), deselect(), step() }: what
  // the keys do (app.js joins them to the page's parts).
  constructor(actions) {
    this.actions = actions;
    this.bindings = [
      ['Space', 'pause or resume', (a) => a.pauseOrResume()],
      ['S', 'step (paused)', (a) => a.step()],
      ['F', 'zoom to fit the scene', (a) => a.fit()],
      ['N', 'names of the bodies on or off', (a) => a.names()],
      ['T', 'trails on or off', (a) => a.trails()],
      ['B', 'put the selected body back (its scene state)', (a) => a.putBack()],
      ['Esc', 'select none; close this help', (a) => { if (!this.close()) a.deselect(); }],
      ['?', 'this help', () => this.toggle()],
    ];
    this.fill();
    $('help-button').onclick = () => this.toggle();
    $('help-close').onclick = () => this.close();
    window.addEventListener('keydown', (event) => this.key(event));
  }

  get shown() {
    return !$('help').hidden;
  }

  toggle(show = !this.shown) {
    $('help').hidden = !show;
  }

  // Closes the help; whether it was open.
  close() {
    const was = this.shown;
    this.toggle(false);
    return was;
  }

  fill() {
    const rows = [...kMouse, ...this.bindings.map(([k, what]) => [k, what])];
    const table = $('help-table');
    table.replaceChildren(...rows.map(([k, what]) => {
      const tr = document.createElement('tr');
      const key = document.createElement('td');
      key.className = 'key';
      key.textContent = k;
      const does = document.createElement('td');
      does.textContent = what;
      tr.append(key, does);
      return tr;
    }));
  }

  key(event) {
    const t = event.target;
    if (event.ctrlKey || event.metaKey || event.altKey) return;
    if (t && (t.tagName === 'INPUT' || t.tagName === 'TEXTAREA' || t.isContentEditable)) return;
    const name = event.key === ' ' ? 'Space' : event.key === 'Escape' ? 'Esc'
      : event.key.length === 1 ? event.key.toUpperCase() : event.key;
    const binding = this.bindings.find(([k]) => k === name);
    if (!binding) return;
    event.preventDefault();
    binding[2](this.actions);
  }
}
