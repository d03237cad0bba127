// Open MCT telemetry metadata (API.md "Telemetry Metadata") for the display's
// telemetry objects, built from the display dictionary: the ground receive
// time "utc" is the domain (the UTC time system's key), the rover's "met" a
// plain value, and each field a value with its key, name, unit, format and,
// for numbers, a range hint (what plots draw).

import { splitArrayKey } from './dictionary.js';
import { enumerationsFor, WHEEL_NAMES } from './enumerations.js';
import { RSE_NUMBER_FORMAT } from './number-format.js';

const UTC_VALUE = {
  key: 'utc',
  source: 'utc',
  name: 'Time (UTC)',
  format: 'utc',
  hints: { domain: 1 }
};

const MET_VALUE = {
  key: 'met',
  name: 'MET',
  unit: 's',
  format: RSE_NUMBER_FORMAT,
  hints: {}
};

// A per-wheel array (six elements whose description or packet says wheel)
// gets the wheel's name after the key: "current.3 (FR)".
export function displayName(dictionary, packetName, field) {
  const name = field.name || field.key;
  const { base, index } = splitArrayKey(field.key);
  if (index < 0 || index >= WHEEL_NAMES.length) {
    return name;
  }
  const perWheel =
    dictionary.arrayKeys(packetName, base).length === WHEEL_NAMES.length &&
    (/wheel|FL ML RL FR MR RR/i.test(field.description || '') ||
      ['DRIVES', 'HEALTH', 'POWER'].includes(packetName));
  return perWheel ? `${name} (${WHEEL_NAMES[index]})` : name;
}

export function isNumeric(field) {
  return field.type !== 'chr' && field.type !== 'string';
}

export function valueMetadata(dictionary, packetName, field, hints) {
  const value = {
    key: field.key,
    source: field.key,
    name: displayName(dictionary, packetName, field),
    hints: { ...hints }
  };
  if (field.units) {
    value.unit = field.units;
  }
  const enumerations = isNumeric(field) ? enumerationsFor(packetName, field) : undefined;
  if (!isNumeric(field)) {
    value.format = 'string';
  } else if (enumerations) {
    value.format = 'enum';
    value.enumerations = enumerations;
    // Set here: Open MCT's own default (Math.max of an array) is NaN.
    const codes = enumerations.map((e) => e.value);
    value.min = Math.min(...codes);
    value.max = Math.max(...codes);
  } else {
    value.format = RSE_NUMBER_FORMAT;
  }
  return value;
}

function timeValues(packet) {
  return packet.fieldByKey.has('met') ? [UTC_VALUE] : [UTC_VALUE, MET_VALUE];
}

// Every field of a packet; numbers ranked as ranges in dictionary order.
export function packetMetadata(dictionary, packetName) {
  const packet = dictionary.packet(packetName);
  let rank = 1;
  const values = packet.fields.filter((field) => field.key !== 'utc').map((field) =>
    valueMetadata(dictionary, packetName, field, isNumeric(field) ? { range: rank++ } : {})
  );
  return { values: [...timeValues(packet), ...values] };
}

// One field as its own telemetry point (what an overlay plot series draws).
export function fieldMetadata(dictionary, packetName, key) {
  const packet = dictionary.packet(packetName);
  const field = packet.fieldByKey.get(key);
  return {
    values: [...timeValues(packet), valueMetadata(dictionary, packetName, field, { range: 1 })]
  };
}
