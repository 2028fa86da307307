// The side panel (index.html's #side, top right): the body list (search by name or id; the first
// kMaxListed matches), the selected body's state and "follow", and the plots: relative drift of
// energy and angular momentum (rigid-view's, drift.js) of the selected body or the largest over
// all bodies, 10 samples a second, and tick lateness p99 from each Stats report.
import { StripChart } from './plot.js';

const $ = (id) => document.getElementById(id);
const kMaxListed = 200;
const kSampleEvery = 100;  // ms between samples of the drift plot
const fmt = (a) => a.map((x) => (Math.abs(x) < 1e-12 ? '0' : x.toPrecision(4))).join(', ');

export class Panel {
  // bodies (bodies.js), selection (selection.js), viewport (viewport.js: follow moves its camera),
  // drift (drift.js: the drifts rigid-view sent).
  constructor(bodies, selection, viewport, drift) {
    this.bodies = bodies;
    this.selection = selection;
    this.viewport = viewport;
    this.drift = drift;
    // The panel follows the plots' 10 samples a second, but a body just selected is shown with the
    // first state that has all of it (selectedShown), not up to a sample later.
    this.selectedShown = false;
    this.stateChanged = false;  // a state since the last sample
    this.nextSample = 0;
    this.driftChart = new StripChart($('plot-drift'), {
      series: [{ name: 'energy', color: '#4fc3f7' }, { name: 'ang. momentum', color: '#ffb74d' }],
      log: true });
    this.latenessChart = new StripChart($('plot-lateness'), {
      series: [{ name: 'tick lateness p99', color: '#81c784' }], unit: ' µs' });
    $('search').oninput = () => this.fillBodyList();
    selection.onChange((b) => this.selected(b));
  }

  fillBodyList() {
    const query = $('search').value.trim().toLowerCase();
    const list = $('bodylist');
    const selected = this.selection.body;
    list.replaceChildren();
    let matches = 0;
    for (const b of this.bodies.list) {
      if (query && !b.name.toLowerCase().includes(query) && String(b.id) !== query) continue;
      if (++matches > kMaxListed) continue;
      const row = document.createElement('div');
      row.textContent = `${b.id} ${b.name}`;
      row.className = b === selected ? 'row sel' : 'row';
      row.onclick = () => this.selection.set(b === this.selection.body ? null : b);
      list.appendChild(row);
    }
    $('listcount').textContent = matches > kMaxListed ? `${kMaxListed} of ${matches}` : `${matches}`;
  }

  selected(b) {
    this.selectedShown = false;
    $('selected').style.display = b ? '' : 'none';
    if (b) $('selname').textContent = `${b.name} (id ${b.id}, ${b.shape}, ${+b.mass.toPrecision(4)} kg)`;
    this.fillBodyList();
    this.driftChart.clear();  // a different quantity from here on
  }

  newScene() {
    this.driftChart.clear();
    this.fillBodyList();
  }

  // After each state applied.
  stateApplied() {
    this.stateChanged = true;
    if (this.selection.body && !this.selectedShown) this.showSelected();
  }

  showSelected() {
    const b = this.selection.body;
    if (!b || !b.placed) return;
    $('selp').textContent = fmt(b.p.toArray());
    $('selq').textContent = fmt([b.q.w, b.q.x, b.q.y, b.q.z]);
    $('selv').textContent = b.moving ? fmt(b.v.toArray()) : '–';
    $('selw').textContent = b.moving ? fmt(b.w.toArray()) : '–';
    this.selectedShown = b.moving;
  }

  // "Follow": the camera keeps its offset from the selected body.
  follow() {
    const b = this.selection.body;
    if (!b || !b.placed || !$('follow').checked) return;
    this.viewport.translate(b.p.clone().sub(this.viewport.controls.target));
  }

  // Stats: their tick lateness into its plot.
  stats(s) {
    if (Number.isFinite(s.lateness_p99_us)) this.latenessChart.push(performance.now() / 1000, [s.lateness_p99_us]);
  }

  // Once per animation frame: a sample of the drifts when it is time and a state came, and the
  // plots redrawn if they changed.
  sample(now) {
    if (now < this.nextSample) return;
    this.nextSample = now + kSampleEvery;
    if (this.stateChanged) {
      this.stateChanged = false;
      const selected = this.selection.body;
      const d = this.drift.worst(selected ? selected.index : -1);
      this.driftChart.push(now / 1000, [d.energy, d.momentum]);
      $('plot-of').textContent = selected ? selected.name : this.worstLabel(d);
      this.showSelected();
    }
    this.driftChart.draw();
    this.latenessChart.draw();
  }

  // "all bodies (max: craft)": the worst body is named, so that a body the scene pushes (whose
  // energy changes by the work done on it) is seen for what it is; click a body for its own drift.
  worstLabel(d) {
    const list = this.bodies.list;
    const name = (i) => (i >= 0 && i < list.length ? list[i].name : null);
    const e = name(d.energyAt), m = name(d.momentumAt);
    if (!e && !m) return 'all bodies (max)';
    return `all bodies (max: ${e === m || !m ? e : !e ? m : `${e}, ${m}`})`;
  }
}
