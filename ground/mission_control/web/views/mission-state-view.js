// The mission-state panel (Open MCT custom view of the "Mission state"
// object): the rover mode and e-stop (HK), the deliberative layer's status,
// goal, leg, risk and call home (PLAN), the plan executive (PLAN_EXEC), the
// fault-protection hold (FAULT_PROTECTION) and the ground link: the realtime
// WebSocket and rse-ground serve's counters (/api/status).

import { html, fixed, timeOfDay } from './dom.js';
import { PacketWatch } from '../lib/packet-watch.js';
import { nameOf } from '../lib/enumerations.js';

const STATUS_POLL_MS = 2000;
const HOLD_REASONS = ['drive recovery', 'pose uncertain', 'battery low', 'sensor lost', 'task restart', 'drive over-temperature', 'off the map'];
const PLAN_CALLED_HOME = 4;
const EXEC_FAILED = 5;

function text(value) {
  return typeof value === 'string' ? value.replace(/\0+$/, '') : value;
}

export class MissionStateView {
  constructor(openmct, state) {
    this.openmct = openmct;
    this.dictionary = state.dictionary;
    this.realtime = state.realtime;
    this.watches = {};
    this.serverStatus = undefined;
  }

  show(element) {
    this.grid = html('div', { class: 'rse-mission-state__grid' });
    element.append(html('div', { class: 'rse-mission-state', id: 'rse-mission-state' }, [this.grid]));
    this.tiles = {};
    for (const [key, label] of [
      ['mode', 'Mode'],
      ['plan', 'Plan'],
      ['goal', 'Goal'],
      ['leg', 'Leg'],
      ['risk', 'Risk in force / used'],
      ['callHome', 'Call home'],
      ['exec', 'Plan executive'],
      ['activities', 'Activities'],
      ['hold', 'Fault protection'],
      ['link', 'Ground link']
    ]) {
      const value = html('div', { class: 'rse-tile__value' });
      const detail = html('div', { class: 'rse-tile__detail' });
      const tile = html('div', { class: 'rse-tile', 'data-tile': key }, [
        html('div', { class: 'rse-tile__label', text: label }),
        value,
        detail
      ]);
      this.grid.append(tile);
      this.tiles[key] = { tile, value, detail };
    }
    for (const packet of ['HK', 'PLAN', 'PLAN_EXEC', 'FAULT_PROTECTION']) {
      if (!this.dictionary.hasPacket(packet)) continue;
      const watch = new PacketWatch(this.openmct, packet, { mode: 'latest', onChange: () => this.#render() });
      this.watches[packet] = watch;
      watch.start();
    }
    this.unlisten = this.realtime.onStatus(() => this.#render());
    this.#pollStatus();
    this.#render();
  }

  destroy() {
    Object.values(this.watches).forEach((w) => w.stop());
    this.unlisten?.();
    clearTimeout(this.pollTimer);
    this.stopped = true;
  }

  async #pollStatus() {
    try {
      const response = await fetch('/api/status');
      this.serverStatus = response.ok ? await response.json() : undefined;
    } catch {
      this.serverStatus = undefined;
    }
    if (this.stopped) return;
    this.#render();
    this.pollTimer = setTimeout(() => this.#pollStatus(), STATUS_POLL_MS);
  }

  #set(key, value, detail = '', level = '') {
    const t = this.tiles[key];
    t.value.textContent = value;
    t.detail.textContent = detail;
    t.tile.className = `rse-tile${level ? ` rse-tile--${level} is-limit--${level === 'alarm' ? 'red' : 'yellow'}` : ''}`;
  }

  #render() {
    const hk = this.watches.HK?.latest;
    const plan = this.watches.PLAN?.latest;
    const exec = this.watches.PLAN_EXEC?.latest;
    const fp = this.watches.FAULT_PROTECTION?.latest;

    this.#set(
      'mode',
      hk ? nameOf('HK', 'mode', hk.mode) : '—',
      hk ? `${hk.estop ? 'E-STOP set · ' : ''}HK ${timeOfDay(hk.utc)}` : 'no HK in the window',
      hk?.estop ? 'alarm' : hk && hk.mode === 0 ? 'warning' : ''
    );

    if (plan) {
      this.#set(
        'plan',
        nameOf('PLAN', 'status', plan.status),
        `${nameOf('PLAN', 'plan_status', plan.plan_status)}, ${fixed(plan.plan_length, 1)} m, ${plan.replans ?? 0} replans`,
        plan.status === PLAN_CALLED_HOME ? 'alarm' : ''
      );
      this.#set('goal', `${Math.min(plan.goal_index + 1, plan.goal_count)} of ${plan.goal_count}`,
        plan.goal_count > 0 ? `(${fixed(plan[`goal_x.${plan.goal_index}`], 1)}, ${fixed(plan[`goal_y.${plan.goal_index}`], 1)}) m` : '');
      this.#set('leg', `${Math.min(plan.leg_index + 1, plan.leg_count)} of ${plan.leg_count}`, `leg id ${plan.current_leg_id ?? '—'}`);
      this.#set('risk', `${Number(plan.risk_in_force).toExponential(1)} / ${Number(plan.risk_used).toExponential(1)}`,
        `operator's bound ${Number(plan.risk_bound).toExponential(1)}`);
      this.#set('callHome', nameOf('PLAN', 'call_home', plan.call_home), `${plan.call_homes ?? 0} since start`,
        plan.call_home ? 'alarm' : '');
    } else {
      for (const key of ['plan', 'goal', 'leg', 'risk', 'callHome']) this.#set(key, '—', 'no PLAN in the window');
    }

    if (exec) {
      this.#set('exec', nameOf('PLAN_EXEC', 'state', exec.state), text(exec.plan_name) || 'no plan',
        exec.state === EXEC_FAILED ? 'alarm' : '');
      this.#set('activities', `${exec.running ?? 0} running of ${exec.activity_count ?? 0}`,
        `${exec.completed ?? 0} done, ${exec.failed ?? 0} failed, ${exec.late ?? 0} late`,
        exec.failed > 0 ? 'warning' : '');
    } else {
      this.#set('exec', '—', 'no PLAN_EXEC in the window');
      this.#set('activities', '—', '');
    }

    if (fp) {
      const reasons = HOLD_REASONS.filter((_, i) => Math.floor(Number(fp.hold_reasons) / 2 ** i) % 2 === 1);
      this.#set('hold', reasons.length ? 'HOLD' : 'no hold', reasons.length ? reasons.join(', ') : `${fp.response_count ?? 0} responses in progress`,
        reasons.length ? 'warning' : '');
    } else {
      this.#set('hold', '—', 'no FAULT_PROTECTION in the window');
    }

    const s = this.serverStatus;
    this.#set(
      'link',
      this.realtime.connected ? 'live' : 'disconnected',
      s ? `${s.packets_received ?? '?'} packets, ${s.decode_errors ?? 0} decode errors, ${s.link ?? ''}` : 'server status unavailable',
      this.realtime.connected ? '' : 'alarm'
    );
  }
}

export function missionStateViewProvider(openmct, state, type) {
  return {
    key: 'rse.mission-state-view',
    name: 'Mission state',
    cssClass: 'icon-dataset',
    canView: (domainObject) => domainObject.type === type,
    view: () => new MissionStateView(openmct, state)
  };
}
