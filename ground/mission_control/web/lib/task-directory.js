// The rate-group tasks, learnt from TASK_TIMING: the rover sends one
// TASK_TIMING packet per task each second, told apart by its task index (and
// named by its task name), so the display splits the packet into one
// telemetry object per task. Which tasks exist is only known from the data:
// the archive's last minutes of the time conductor's window first, else the
// live stream for a few seconds.

export const TASK_PACKET = 'TASK_TIMING';
export const TASK_INDEX_KEY = 'task_index';
export const TASK_NAME_KEY = 'task_name';

const LOOKBACK_MS = 2 * 60 * 1000; // every task is sent each second
const WAIT_MS = 3000; // the tasks are sent within one second of each other
const SETTLE_MS = 1200;

export class TaskDirectory {
  constructor({ dictionary, realtime, requestHistory, timeBounds }) {
    this.timeBounds = timeBounds;
    this.available =
      dictionary.hasPacket(TASK_PACKET) && Boolean(dictionary.field(TASK_PACKET, TASK_INDEX_KEY));
    this.tasks = new Map(); // index -> name
    this.requestHistory = requestHistory;
    this.realtime = realtime;
    this.discovery = undefined;
    this.changeListeners = new Set();
    if (this.available) {
      // Kept for the page's life: new tasks and renamed ones are seen as they come.
      realtime.subscribe(TASK_PACKET, (datum) => this.observe(datum));
    }
  }

  observe(datum) {
    const index = Number(datum[TASK_INDEX_KEY]);
    if (!Number.isInteger(index) || index < 0) {
      return;
    }
    const name = String(datum[TASK_NAME_KEY] ?? '').replace(/\0+$/, '').trim() || `task ${index}`;
    if (this.tasks.get(index) !== name) {
      this.tasks.set(index, name);
      for (const callback of this.changeListeners) callback();
    }
  }

  list() {
    return [...this.tasks]
      .sort((a, b) => a[0] - b[0])
      .map(([index, name]) => ({ index, name }));
  }

  nameOf(index) {
    return this.tasks.get(index) || `task ${index}`;
  }

  // The tasks known once the recent archive was read, or the live stream
  // watched, whichever finds some first (or none after WAIT_MS); later calls
  // add the tasks seen live since.
  async discover() {
    if (!this.available) {
      return [];
    }
    if (!this.discovery) {
      this.discovery = this.#discover().finally(() => {
        // Run again next time when nothing was found (the rover was silent).
        if (this.tasks.size === 0) this.discovery = undefined;
      });
    }
    await this.discovery;
    return this.list();
  }

  async #discover() {
    const { start, end } = this.timeBounds();
    try {
      const datums = await this.requestHistory(TASK_PACKET, Math.max(start, end - LOOKBACK_MS), end);
      datums.forEach((d) => this.observe(d));
    } catch (error) {
      console.warn('task discovery: history', error);
    }
    if (this.tasks.size === 0) {
      await this.#watchLive();
    }
    return this.list();
  }

  // Resolves SETTLE_MS after the last new task seen live, or at WAIT_MS.
  #watchLive() {
    return new Promise((resolve) => {
      let settle;
      let timeout;
      const done = () => {
        clearTimeout(timeout);
        clearTimeout(settle);
        this.changeListeners.delete(listener);
        resolve();
      };
      const listener = () => {
        clearTimeout(settle);
        settle = setTimeout(done, SETTLE_MS);
      };
      timeout = setTimeout(done, WAIT_MS);
      this.changeListeners.add(listener);
    });
  }
}
