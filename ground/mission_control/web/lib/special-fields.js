// Where the special views and ready-made plots find the quantities of the
// packets that may or may not be in the dictionary: POWER (battery voltage,
// state of charge, per-wheel motor temperature) and HAZARDS (the hazards
// seen: x, y and radius arrays with a count). Their field names are matched
// loosely (by key and units), so a rename within reason still works; a
// packet or field not found leaves its view without it, never broken.

function scalarFields(dictionary, packetName) {
  const packet = dictionary.packet(packetName);
  return packet ? packet.fields.filter((f) => !/\.\d+$/.test(f.key)) : [];
}

function firstMatch(fields, tests) {
  for (const test of tests) {
    const found = fields.find(test);
    if (found) return found.key;
  }
  return undefined;
}

export function powerFields(dictionary) {
  if (!dictionary.hasPacket('POWER')) {
    return { present: false, motorTemperatures: [] };
  }
  const scalars = scalarFields(dictionary, 'POWER');
  const voltage = firstMatch(scalars, [
    (f) => /batt.*volt|volt.*batt/i.test(f.key),
    (f) => /volt/i.test(f.key),
    (f) => f.units === 'V'
  ]);
  const stateOfCharge = firstMatch(scalars, [
    (f) => /(^|_)soc($|_)|state_of_charge/i.test(f.key),
    (f) => /charge/i.test(f.key) && !/current|rate/i.test(f.key),
    (f) => f.units === '%'
  ]);
  const temperatureArray = dictionary
    .arrays('POWER')
    .find((a) => a.count === 6 && /temp/i.test(a.base));
  return {
    present: true,
    voltage,
    stateOfCharge,
    motorTemperatures: temperatureArray ? dictionary.arrayKeys('POWER', temperatureArray.base) : []
  };
}

export function hazardFields(dictionary) {
  if (!dictionary.hasPacket('HAZARDS')) {
    return { present: false };
  }
  const arrays = dictionary.arrays('HAZARDS');
  const pick = (tests) => {
    for (const test of tests) {
      const found = arrays.find((a) => test(a.base));
      if (found) return found.base;
    }
    return undefined;
  };
  const x = pick([(b) => b === 'x', (b) => /(^|_)x$/.test(b)]);
  const y = pick([(b) => b === 'y', (b) => /(^|_)y$/.test(b)]);
  const radius = pick([(b) => b === 'radius', (b) => /radius|(^|_)r$/.test(b)]);
  const count = firstMatch(scalarFields(dictionary, 'HAZARDS'), [
    (f) => f.key === 'count',
    (f) => /count/i.test(f.key)
  ]);
  return { present: Boolean(x && y), x, y, radius, count };
}
