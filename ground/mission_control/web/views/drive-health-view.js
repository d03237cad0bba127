// The drive-health panel (Open MCT custom view of the "Drive health" object):
// one row per wheel (FL ML RL FR MR RR) with its drive state and speeds
// (DRIVES), the health monitor's mode estimate (HEALTH drive_mode and
// p_nominal), its motor current (DRIVES) and temperature (POWER, when the
// dictionary has it), and its faults: the wheel's active fault bits in HEALTH
// (heartbeat lost, over-current, over-temperature; docs/estimator.md), a
// CANopen emergency code (DRIVES last_emcy) and a fault-protection response
// in progress (FAULT_PROTECTION). Cells beyond the dictionary's limits take
// Open MCT's limit colours; a row takes the worst of its wheel.

import { html, fixed, bit, timeOfDay } from './dom.js';
import { PacketWatch } from '../lib/packet-watch.js';
import { fieldLimits, limitCssClass, limitState } from '../lib/limits.js';
import { nameOf, WHEEL_NAMES } from '../lib/enumerations.js';
import { powerFields } from '../lib/special-fields.js';

// HEALTH.active_faults bit ids per wheel w (docs/estimator.md, Faults).
const WHEEL_FAULTS = [
  { first: 1, name: 'heartbeat lost' },
  { first: 11, name: 'over-current' },
  { first: 40, name: 'over-temperature' }
];
const DRIVE_STATE_OPERATIONAL = 4;
const DRIVE_STATE_FAULTED = 5; // 5 faulted, 6 failed, 7 lost
const MODE_NOMINAL = 0;
const MODE_FAILED = 2;
// FAULT_PROTECTION fault classes that answer a drive fault (fault_id = 1 + wheel).
const DRIVE_FAULT_CLASSES = new Set([0, 1, 2, 8]);
const RESPONSE_STATES = ['idle', 'settling', 'waiting for clear', 'recovered', 'gave up'];

const SEVERITY = { ok: 0, warning: 1, alarm: 2 };
const ALARM_CLASS = { warning: 'is-limit--yellow', alarm: 'is-limit--red' };

export class DriveHealthView {
  constructor(openmct, dictionary) {
    this.openmct = openmct;
    this.dictionary = dictionary;
    this.power = powerFields(dictionary);
    this.watches = {};
  }

  show(element) {
    this.summary = html('div', { class: 'rse-drive-health__summary', id: 'rse-drive-summary' });
    this.body = html('tbody');
    const headers = ['Wheel', 'State', 'Mode (p nom.)', 'Speed/cmd rad/s', 'Current A', 'Temp °C', 'Faults'];
    element.append(
      html('div', { class: 'rse-drive-health', id: 'rse-drive-health' }, [
        this.summary,
        html('table', { class: 'rse-drive-health__table' }, [
          html('thead', {}, [html('tr', {}, headers.map((h) => html('th', { text: h })))]),
          this.body
        ])
      ])
    );
    this.rows = WHEEL_NAMES.map((wheel, w) => {
      const cells = headers.map(() => html('td'));
      cells[0].textContent = wheel;
      const row = html('tr', { class: 'rse-wheel', 'data-wheel': wheel, 'data-index': w }, cells);
      this.body.append(row);
      return { row, cells };
    });
    for (const packet of ['DRIVES', 'HEALTH', 'FAULT_PROTECTION', ...(this.power.motorTemperatures.length ? ['POWER'] : [])]) {
      if (!this.dictionary.hasPacket(packet)) continue;
      const watch = new PacketWatch(this.openmct, packet, { mode: 'latest', onChange: () => this.#render() });
      this.watches[packet] = watch;
      watch.start();
    }
    this.#render();
  }

  destroy() {
    Object.values(this.watches).forEach((w) => w.stop());
  }

  #limitClass(packet, key, value) {
    const field = this.dictionary.field(packet, key);
    return field ? limitCssClass(limitState(value, fieldLimits(packet, field))) : '';
  }

  #render() {
    const drives = this.watches.DRIVES?.latest;
    const health = this.watches.HEALTH?.latest;
    const power = this.watches.POWER?.latest;
    const protection = this.watches.FAULT_PROTECTION?.latest;
    this.rows.forEach(({ row, cells }, w) => {
      let severity = SEVERITY.ok;
      const raise = (level) => (severity = Math.max(severity, SEVERITY[level]));
      const set = (cell, text, cls = '') => {
        cell.textContent = text;
        cell.className = cls;
        if (/is-limit--red/.test(cls)) raise('alarm');
        else if (/is-limit--yellow/.test(cls)) raise('warning');
      };

      const state = drives?.[`state.${w}`];
      const stateLevel =
        state === undefined ? '' : state >= DRIVE_STATE_FAULTED ? 'alarm' : state !== DRIVE_STATE_OPERATIONAL ? 'warning' : '';
      set(cells[1], drives ? nameOf('DRIVES', 'state', state) : '—', stateLevel ? ALARM_CLASS[stateLevel] : '');

      const mode = health?.[`drive_mode.${w}`];
      const pNominal = health?.[`p_nominal.${w}`];
      const modeLevel = mode === undefined || mode === MODE_NOMINAL ? '' : mode === MODE_FAILED ? 'alarm' : 'warning';
      set(
        cells[2],
        health ? `${nameOf('HEALTH', 'drive_mode', mode)}${pNominal !== undefined ? ` (${fixed(pNominal, 2)})` : ''}` : '—',
        modeLevel ? ALARM_CLASS[modeLevel] : ''
      );

      set(cells[3], drives ? `${fixed(drives[`speed.${w}`], 2)} / ${fixed(drives[`commanded.${w}`], 2)}` : '—');
      set(cells[4], fixed(drives?.[`current.${w}`], 2), this.#limitClass('DRIVES', `current.${w}`, drives?.[`current.${w}`]));

      const temperatureKey = this.power.motorTemperatures[w];
      if (!temperatureKey) set(cells[5], 'n/a');
      else set(cells[5], fixed(power?.[temperatureKey], 1), this.#limitClass('POWER', temperatureKey, power?.[temperatureKey]));

      const faults = this.#faults(w, drives, health, protection);
      set(cells[6], faults.length ? faults.join('; ') : 'none', faults.length ? ALARM_CLASS.alarm : '');

      row.className = `rse-wheel rse-wheel--${Object.keys(SEVERITY)[severity]}`;
      row.dataset.severity = Object.keys(SEVERITY)[severity];
    });
    this.#renderSummary(drives, health);
  }

  #faults(w, drives, health, protection) {
    const faults = [];
    if (health && health.active_faults !== undefined) {
      for (const fault of WHEEL_FAULTS) {
        if (bit(health.active_faults, fault.first + w)) faults.push(fault.name);
      }
    }
    const emcy = Number(drives?.[`last_emcy.${w}`]);
    if (emcy > 0) faults.push(`EMCY 0x${emcy.toString(16).padStart(4, '0')}`);
    const count = Number(protection?.response_count) || 0;
    for (let i = 0; i < count; i++) {
      if (
        Number(protection[`fault_id.${i}`]) === 1 + w &&
        DRIVE_FAULT_CLASSES.has(Number(protection[`fault_class.${i}`]))
      ) {
        const state = Number(protection[`state.${i}`]);
        faults.push(`recovery: ${RESPONSE_STATES[state] ?? state}`);
      }
    }
    return faults;
  }

  #renderSummary(drives, health) {
    const parts = [];
    if (!drives) parts.push('no DRIVES in the window');
    else {
      if (drives.interlock) parts.push('INTERLOCK: every drive held at zero');
      if (drives.estop) parts.push('E-STOP set');
      parts.push(`drives at ${timeOfDay(drives.utc)}`);
    }
    if (health) parts.push(`health at ${timeOfDay(health.utc)}`);
    if (!this.power.motorTemperatures.length) parts.push('no motor temperatures in the dictionary');
    this.summary.textContent = parts.join(' · ');
    this.summary.className = `rse-drive-health__summary${drives?.interlock || drives?.estop ? ' is-limit--red' : ''}`;
  }
}

export function driveHealthViewProvider(openmct, state, type) {
  return {
    key: 'rse.drive-health-view',
    name: 'Drive health',
    cssClass: 'icon-tabular-lad',
    canView: (domainObject) => domainObject.type === type,
    view: () => new DriveHealthView(openmct, state.dictionary)
  };
}
