// Names of the coded values the display shows as text (event severity, rover
// mode, drive state, ...). The display dictionary carries no enumerations, so
// these are copied from the field descriptions in docs/dictionary.md (and
// fsw/msg/drive_msgs.hpp for the drive states); a field the dictionary gives
// its own "enumerations" for uses those instead. A value with no name shows as
// its number. unit_test/ground/mission_control/web/web_lib.test.mjs holds every name here
// to the value the dictionary's description gives it (docs/dictionary.json,
// itself checked against the flight dictionary), so they cannot drift apart.

import { splitArrayKey } from './dictionary.js';

// Wheel order of every per-wheel array (fsw/msg/drive_msgs.hpp, kWheelCount).
export const WHEEL_NAMES = ['FL', 'ML', 'RL', 'FR', 'MR', 'RR'];

export const NAMES = {
  'EVENT.severity': ['DEBUG', 'INFO', 'WARN', 'ERROR', 'CRIT'],
  'HK.mode': ['SAFE', 'STANDBY', 'AUTONOMOUS', 'MANUAL'],
  'DRIVES.state': [
    'boot-up wait',
    'configuring',
    'starting',
    'enabling',
    'operational',
    'faulted',
    'failed',
    'lost'
  ],
  'HEALTH.drive_mode': ['nominal', 'degraded', 'failed', 'unknown'],
  'PLAN.status': ['idle', 'waiting', 'planning', 'executing', 'called home', 'every goal reached'],
  'PLAN.plan_status': ['optimal', 'budget plan', 'no plan', 'bad problem'],
  'PLAN.call_home': [
    'no',
    'no plan within the risk limit',
    'goal unreachable',
    'replans exhausted',
    'insufficient power',
    'mobility lost'
  ],
  'PLAN_EXEC.state': ['idle', 'selecting', 'dispatching', 'regenerating', 'complete', 'failed'],
  'PLAN_PATH.status': ['optimal', 'budget plan']
};

// [{value, string}] for a field, or undefined when its values have no names.
export function enumerationsFor(packetName, field) {
  if (Array.isArray(field.enumerations) && field.enumerations.length > 0) {
    return field.enumerations;
  }
  const names = NAMES[`${packetName}.${splitArrayKey(field.key).base}`];
  return names ? names.map((string, value) => ({ value, string })) : undefined;
}

// The name of one value, or the value itself as text.
export function nameOf(packetName, fieldKey, value) {
  const names = NAMES[`${packetName}.${splitArrayKey(fieldKey).base}`];
  if (names && Number.isInteger(value) && value >= 0 && value < names.length) {
    return names[value];
  }
  return value === undefined || value === null ? '—' : String(value);
}
