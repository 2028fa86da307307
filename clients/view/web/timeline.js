// The playback timeline of rigid-view FILE (shown only when hello says "mode":"playback"): play /
// pause, a slider over the recording's timeline [start, end] (its sim time), the state shown (sim
// time, tick, index) and the speed. It sends play, pause, seek and speed (protocol.hpp) through
// `control` and draws what rigid-view answers in its "playback" messages, so that every page
// shows the one playback they share.
const kSpeeds = [1 / 16, 1 / 8, 1 / 4, 1 / 2, 1, 2, 4, 8, 16];

const kStyle = `
  #timeline { position: absolute; left: 8px; right: 8px; bottom: 8px; display: flex; gap: 10px;
              align-items: center; background: rgba(0,0,0,0.55); padding: 6px 10px;
              border-radius: 6px; }
  #timeline[hidden] { display: none; }
  #timeline button, #timeline select { font: inherit; }
  #tl-play { min-width: 4.5em; }
  #tl-slider { flex: 1; }
  #tl-time { font-variant-numeric: tabular-nums; white-space: nowrap; min-width: 22em; }
`;

function element(tag, props = {}) {
  return Object.assign(document.createElement(tag), props);
}

// control(op, extra): sends a command with a fresh id (app.js).
export function createTimeline(control) {
  const style = element('style', { textContent: kStyle });
  document.head.appendChild(style);
  const bar = element('div', { id: 'timeline', hidden: true });
  const play = element('button', { id: 'tl-play', textContent: 'play' });
  const slider = element('input', { id: 'tl-slider', type: 'range', min: '0', max: '1',
                                    step: 'any', value: '0' });
  const time = element('span', { id: 'tl-time', textContent: '–' });
  const speed = element('select', { id: 'tl-speed', title: 'playback speed' });
  for (const s of kSpeeds) {
    speed.appendChild(element('option', { value: String(s), textContent: `${s}×`,
                                          selected: s === 1 }));
  }
  const name = element('span', { id: 'tl-file' });
  bar.append(play, slider, time, speed, name);
  document.body.appendChild(bar);

  let status = null;       // the last "playback" message
  let statusAt = 0;        // performance.now() when it came
  let dragging = false;    // the user holds the slider: rigid-view's position does not move it
  let pendingSeek = null;  // one seek per animation frame while dragging

  play.onclick = () => control(status && status.playing ? 'pause' : 'play');
  speed.onchange = () => control('speed', { speed: Number(speed.value) });
  slider.addEventListener('pointerdown', () => { dragging = true; });
  const endDrag = () => { dragging = false; };
  slider.addEventListener('pointerup', endDrag);
  slider.addEventListener('pointercancel', endDrag);
  slider.addEventListener('change', endDrag);
  slider.addEventListener('input', () => {
    if (pendingSeek === null) {
      requestAnimationFrame(() => {
        control('seek', { time: pendingSeek });
        pendingSeek = null;
      });
    }
    pendingSeek = Number(slider.value);
  });

  // While playing, the slider moves on between rigid-view's messages (4 a second) at the speed.
  function place() {
    if (!status || dragging) return;
    let p = status.position;
    if (status.playing) {
      p = Math.min(status.end, p + status.speed * (performance.now() - statusAt) / 1000);
    }
    slider.value = String(p);
  }
  (function animate() {
    place();
    requestAnimationFrame(animate);
  })();

  return {
    show(readOnly) {
      bar.hidden = false;
      for (const e of [play, slider, speed]) e.disabled = readOnly;  // rigid-view refuses anyway
    },
    // A "playback" message from rigid-view.
    update(msg) {
      status = msg;
      statusAt = performance.now();
      slider.min = String(msg.start);
      slider.max = String(msg.end > msg.start ? msg.end : msg.start + 1e-9);
      play.textContent = msg.playing ? 'pause' : 'play';
      time.textContent = `t = ${msg.sim_time.toFixed(3)} s · tick ${msg.tick} · ` +
                         `${msg.index + 1}/${msg.states}`;
      if (Number(speed.value) !== msg.speed) {
        const option = [...speed.options].find((o) => Number(o.value) === msg.speed);
        if (option) speed.value = option.value;
      }
      name.textContent = msg.file;
      place();
    },
  };
}
