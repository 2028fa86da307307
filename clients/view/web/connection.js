// The page's connection to rigid-view (reconnected when it goes away): its WebSocket, received on
// a Worker's thread (worker_socket.js: large state frames arrive whole); the JSON messages handed
// to their handlers by type; the state frames kept for the next animation frame and acknowledged
// once it is drawn; commands sent with fresh ids; hello's answer (read-only, live or playback).
import { kAckCommand, kWatchLifetime } from './protocol.js';
import { WorkerSocket } from './worker_socket.js';

// The watch (protocol.hpp: the body whose exact state this page is sent) is re-sent while it
// holds, three times in rigid-view's lifetime of it.
const kWatchEvery = (kWatchLifetime * 1000) / 3;  // ms
const kKeptAnswers = 100;  // replies and errors kept for window.rigidView

export class Connection {
  // handlers: { open(), close(), message(msg): each JSON message, once the connection has taken
  // what it keeps (hello's mode, the last playback, replies and errors), state(): a state frame
  // came }.
  constructor(handlers) {
    this.handlers = handlers;
    this.socket = null;
    this.connected = false;
    this.readOnly = false;
    this.id = 0;          // hello's connection number
    this.mode = 'live';   // or 'playback' (rigid-view FILE)
    this.playback = null;  // the last "playback" message (where the timeline is)
    this.replies = [];    // the last answers to commands, and the last refusals of a frame
    this.errors = [];
    // The newest state frame received and not applied yet ({ data, receivedAt, receivedWall }, from
    // the socket): the next animation frame applies it at its start. rigid-view keeps several
    // states in flight (server.hpp, kMaxUnackedStates), so that a state published just before a
    // frame can be there for it; when more than one comes between two frames only the newest is
    // decoded, and every one is acknowledged when that frame is drawn.
    this.newestState = null;
    this.statesToAck = 0;     // state frames received and not yet drawn
    this.statesReceived = 0;  // state frames received, and those a newer one replaced unapplied
    this.statesSkipped = 0;
    this.nextId = 1;
    this.watched = () => null;  // the id of the body this page watches, or null (app.js sets it)
    setInterval(() => { if (this.watched() !== null) this.watch(); }, kWatchEvery);
  }

  get open() {
    return this.socket !== null && this.socket.readyState === WebSocket.OPEN;
  }

  connect() {
    const socket = new WorkerSocket(`ws://${location.host}/ws`);
    this.socket = socket;
    socket.onopen = () => {
      this.statesToAck = 0;  // a new connection: nothing is owed
      this.newestState = null;
      this.connected = true;
      this.handlers.open();
    };
    socket.onclose = () => {
      this.connected = false;
      this.handlers.close();
      setTimeout(() => this.connect(), 1000);
    };
    socket.onmessage = (event) => {
      if (event.data instanceof ArrayBuffer) {
        this.statesReceived += 1;
        if (this.newestState) this.statesSkipped += 1;
        this.newestState = event;
        this.statesToAck += 1;
        this.handlers.state();
        return;
      }
      const msg = JSON.parse(event.data);
      switch (msg.type) {
        case 'hello':
          this.readOnly = msg.read_only;
          this.id = msg.connection;
          this.mode = msg.mode || 'live';
          break;
        case 'scene': this.newestState = null; break;  // the old scene's (still acknowledged)
        case 'playback': this.playback = msg; break;
        case 'reply': keep(this.replies, msg); break;
        case 'error': keep(this.errors, msg.message); break;
        default: break;
      }
      this.handlers.message(msg);
    };
  }

  // The newest state frame received since the last call, or null.
  takeState() {
    const s = this.newestState;
    this.newestState = null;
    return s;
  }

  // After a frame is drawn: rigid-view may send the next states (it keeps at most four
  // unacknowledged), one for each received since the last frame, applied or replaced.
  acknowledge() {
    for (; this.statesToAck > 0; --this.statesToAck)
      if (this.open) this.socket.send(kAckCommand);
  }

  // A message (an object, sent as JSON); whether it went (false: not connected).
  send(message) {
    if (!this.open) return false;
    this.socket.send(JSON.stringify(message));
    return true;
  }

  // A command with a fresh id ({ op, id, ...extra }): its id, or null when not connected.
  command(op, extra = {}) {
    const id = this.nextId++;
    return this.send({ op, id, ...extra }) ? id : null;
  }

  // Asks rigid-view for the whole state of the body watched() names (large live scenes: pose
  // frames carry it for the bodies watched only), or for none.
  watch() {
    if (!this.open || this.mode === 'playback') return;
    const id = this.watched();
    this.send(id !== null ? { op: 'watch', body: id } : { op: 'watch' });
  }
}

function keep(list, item) {
  list.push(item);
  if (list.length > kKeptAnswers) list.shift();
}
