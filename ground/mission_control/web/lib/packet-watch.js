// What a custom view of the display shows of one packet: its datums in the
// time conductor's bounds (history through Open MCT's telemetry API, then
// realtime through its subscription), reloaded when the operator changes the
// bounds. "latest" keeps only the newest datum; "all" every one, oldest first.
// wholeArchive looks back to the start of the archive for a packet sent only
// now and then (PLAN_PATH: one per plan), whose latest datum may be older than
// the window.

import { packetKey, NAMESPACE } from './rse-objects.js';

export class PacketWatch {
  constructor(openmct, packetName, { mode = 'latest', wholeArchive = false, onChange }) {
    this.openmct = openmct;
    this.packetName = packetName;
    this.mode = mode;
    this.wholeArchive = wholeArchive;
    this.onChange = onChange;
    this.datums = [];
    this.available = undefined; // known once the object is looked up
    this.loadNumber = 0;
    this.duringLoad = []; // realtime datums that came while a history request was out
    this.stopped = false;
    this.onBounds = (bounds, tick) => {
      if (!tick) this.#load();
    };
  }

  get latest() {
    return this.datums[this.datums.length - 1];
  }

  async start() {
    const object = await this.openmct.objects.get(`${NAMESPACE}:${packetKey(this.packetName)}`);
    if (this.stopped) return;
    this.available = Boolean(object && object.telemetry);
    if (!this.available) {
      this.onChange(this);
      return;
    }
    this.object = object;
    this.unsubscribe = this.openmct.telemetry.subscribe(object, (datum) => this.#realtime(datum));
    this.openmct.time.on('boundsChanged', this.onBounds);
    await this.#load();
  }

  stop() {
    this.stopped = true;
    this.unsubscribe?.();
    this.openmct.time.off('boundsChanged', this.onBounds);
  }

  #realtime(datum) {
    // Looking at a fixed past interval, live data after it is not shown.
    if (this.openmct.time.isFixed() && datum.utc > this.openmct.time.getBounds().end) return;
    if (this.loading) this.duringLoad.push(datum);
    this.#add([datum]);
    this.onChange(this);
  }

  #add(datums) {
    for (const datum of datums) {
      const last = this.latest;
      if (this.mode === 'latest') {
        if (!last || datum.utc >= last.utc) this.datums = [datum];
      } else if (!last || datum.utc >= last.utc) {
        this.datums.push(datum);
      } else {
        const at = this.datums.findIndex((d) => d.utc > datum.utc);
        this.datums.splice(at, 0, datum);
      }
    }
  }

  async #load() {
    const number = ++this.loadNumber;
    this.duringLoad = [];
    this.loading = true;
    const bounds = this.openmct.time.getBounds();
    const options = { start: this.wholeArchive ? 0 : bounds.start, end: bounds.end };
    if (this.mode === 'latest') {
      options.strategy = 'latest';
      options.size = 1;
    }
    let datums;
    try {
      datums = await this.openmct.telemetry.request(this.object, options);
    } catch (error) {
      console.warn(`history of ${this.packetName}`, error);
      if (number === this.loadNumber) this.loading = false;
      return;
    }
    if (this.stopped || number !== this.loadNumber) return;
    this.loading = false;
    // Realtime datums that came during the request and are newer than its answer stay.
    const newest = datums.length ? datums[datums.length - 1].utc : -Infinity;
    const live = this.duringLoad.filter((d) => d.utc > newest && d.utc >= options.start);
    this.duringLoad = [];
    this.datums = [];
    this.#add(datums);
    this.#add(live);
    this.onChange(this);
  }
}
