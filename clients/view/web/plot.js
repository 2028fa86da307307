// A small strip chart on a canvas: the last `capacity` samples of a few series against time, in a
// fixed-size ring buffer (no allocation per sample). Written here rather than taken from npm
// (uPlot, Chart.js): the page plots three numbers at a few Hz, and ~100 lines cost less to serve
// and review than a pinned library with its stylesheet.
export class StripChart {
  // series: [{ name, color }]; log: plot log10 of the values (drifts span 1e-16 .. 1).
  constructor(canvas, { series, capacity = 600, log = false, unit = '' }) {
    this.canvas = canvas;
    this.series = series;
    this.capacity = capacity;
    this.log = log;
    this.unit = unit;
    this.t = new Float64Array(capacity);
    this.v = series.map(() => new Float64Array(capacity));
    this.start = 0;
    this.count = 0;
    this.received = 0;  // samples since the page opened (for tests)
    // Whether the canvas shows older samples than these: draw() redraws only then (the page calls
    // it every frame; samples come a few times a second, or none while the scene is paused).
    this.changed = true;
    this.drawn = 0;  // redraws (for tests)
  }

  clear() {
    this.start = 0;
    this.count = 0;
    this.changed = true;
  }

  push(t, values) {
    const at = (this.start + this.count) % this.capacity;
    this.t[at] = t;
    this.series.forEach((_, k) => { this.v[k][at] = values[k]; });
    if (this.count < this.capacity) ++this.count;
    else this.start = (this.start + 1) % this.capacity;
    ++this.received;
    this.changed = true;
  }

  // The newest sample's values, or null.
  last() {
    if (!this.count) return null;
    const at = (this.start + this.count - 1) % this.capacity;
    return this.v.map((v) => v[at]);
  }

  value(x) {
    if (!this.log) return x;
    return Math.log10(Math.max(Math.abs(x), 1e-17));
  }

  draw() {
    if (!this.changed) return;
    this.changed = false;
    ++this.drawn;
    const c = this.canvas, ctx = c.getContext('2d');
    const w = c.width, h = c.height, left = 44, top = 4, bottom = 14;
    ctx.clearRect(0, 0, w, h);
    ctx.font = '10px system-ui, sans-serif';
    if (!this.count) return;
    const at = (i) => (this.start + i) % this.capacity;
    const t0 = this.t[at(0)], t1 = this.t[at(this.count - 1)];
    let lo = Infinity, hi = -Infinity;
    for (const v of this.v) {
      for (let i = 0; i < this.count; ++i) {
        const y = this.value(v[at(i)]);
        if (Number.isFinite(y)) { lo = Math.min(lo, y); hi = Math.max(hi, y); }
      }
    }
    if (!Number.isFinite(lo)) return;
    if (this.log) { lo = Math.floor(lo); hi = Math.ceil(hi); }
    if (hi - lo < 1e-12) { hi += 0.5; lo -= 0.5; }
    const X = (t) => left + ((t - t0) / Math.max(t1 - t0, 1e-9)) * (w - left - 4);
    const Y = (y) => top + (1 - (y - lo) / (hi - lo)) * (h - top - bottom);
    ctx.strokeStyle = '#555';
    ctx.fillStyle = '#aaa';
    ctx.beginPath();
    ctx.moveTo(left, top);
    ctx.lineTo(left, h - bottom);
    ctx.lineTo(w, h - bottom);
    ctx.stroke();
    const label = (y) => (this.log ? `1e${Math.round(y)}` : `${+y.toPrecision(3)}${this.unit}`);
    ctx.fillText(label(hi), 2, top + 8);
    ctx.fillText(label(lo), 2, h - bottom);
    ctx.fillText(`${(t1 - t0).toFixed(1)} s`, w - 40, h - 2);
    this.series.forEach((s, k) => {
      ctx.strokeStyle = s.color;
      ctx.beginPath();
      let pen = false;
      for (let i = 0; i < this.count; ++i) {
        const y = this.value(this.v[k][at(i)]);
        if (!Number.isFinite(y)) { pen = false; continue; }
        if (pen) ctx.lineTo(X(this.t[at(i)]), Y(y));
        else ctx.moveTo(X(this.t[at(i)]), Y(y));
        pen = true;
      }
      ctx.stroke();
      ctx.fillStyle = s.color;
      ctx.fillText(s.name, left + 6 + 90 * k, top + 8);
    });
  }
}
