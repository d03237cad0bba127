// The one WebSocket to rse-ground serve's /realtime (docs/mission_control.md):
// packets are subscribed on demand, {"subscribe": NAME} when the first
// listener of a packet comes and {"unsubscribe": NAME} when its last goes, and
// every {"packet": NAME, "datum": {...}} received goes to that packet's
// listeners. A dropped connection is reopened (the server may restart) and
// every packet still listened to is subscribed again.

const RECONNECT_MIN_MS = 500;
const RECONNECT_MAX_MS = 5000;

export function realtimeUrl(location = window.location) {
  const scheme = location.protocol === 'https:' ? 'wss:' : 'ws:';
  return `${scheme}//${location.host}/realtime`;
}

export class RealtimeLink {
  constructor(url = realtimeUrl()) {
    this.url = url;
    this.listeners = new Map(); // packet -> Set of callbacks
    this.socket = undefined;
    this.connected = false;
    this.reconnectMs = RECONNECT_MIN_MS;
    this.reconnectTimer = undefined;
    this.statusListeners = new Set();
    // Counts for the operator (mission state view) and the browser test.
    this.received = new Map(); // packet -> datums received
    this.connects = 0;
  }

  subscribe(packet, callback) {
    let set = this.listeners.get(packet);
    if (!set) {
      set = new Set();
      this.listeners.set(packet, set);
      this.#send({ subscribe: packet });
    }
    set.add(callback);
    this.#ensureSocket();
    return () => {
      const current = this.listeners.get(packet);
      if (!current || !current.delete(callback) || current.size > 0) {
        return;
      }
      this.listeners.delete(packet);
      this.#send({ unsubscribe: packet });
    };
  }

  onStatus(callback) {
    this.statusListeners.add(callback);
    callback(this.connected);
    return () => this.statusListeners.delete(callback);
  }

  #ensureSocket() {
    if (this.socket || this.reconnectTimer) {
      return;
    }
    const socket = new WebSocket(this.url);
    this.socket = socket;
    socket.addEventListener('open', () => {
      this.connected = true;
      this.connects += 1;
      this.reconnectMs = RECONNECT_MIN_MS;
      for (const packet of this.listeners.keys()) {
        this.#send({ subscribe: packet });
      }
      this.#status();
    });
    socket.addEventListener('message', (event) => this.#receive(event.data));
    socket.addEventListener('close', () => {
      this.socket = undefined;
      this.connected = false;
      this.#status();
      this.reconnectTimer = setTimeout(() => {
        this.reconnectTimer = undefined;
        this.#ensureSocket();
      }, this.reconnectMs);
      this.reconnectMs = Math.min(this.reconnectMs * 2, RECONNECT_MAX_MS);
    });
    // An error is followed by close, which schedules the reconnection.
    socket.addEventListener('error', () => {});
  }

  #send(message) {
    if (this.socket && this.socket.readyState === WebSocket.OPEN) {
      this.socket.send(JSON.stringify(message));
    }
  }

  #receive(text) {
    let message;
    try {
      message = JSON.parse(text);
    } catch {
      console.warn('realtime: message is not JSON', text);
      return;
    }
    for (const one of Array.isArray(message) ? message : [message]) {
      if (!one || typeof one.packet !== 'string' || !one.datum || typeof one.datum !== 'object') {
        continue;
      }
      this.received.set(one.packet, (this.received.get(one.packet) || 0) + 1);
      const set = this.listeners.get(one.packet);
      if (set) {
        for (const callback of [...set]) {
          try {
            callback(one.datum);
          } catch (error) {
            console.error('realtime listener of', one.packet, error);
          }
        }
      }
    }
  }

  #status() {
    for (const callback of this.statusListeners) {
      callback(this.connected);
    }
  }
}
