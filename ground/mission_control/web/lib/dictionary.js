// The display dictionary served by rse-ground serve at /api/dictionary
// (docs/mission_control.md): packets with their fields, array fields already
// expanded to "<field>.<i>". Everything the display shows is derived from it,
// so a packet or field added to the flight dictionary appears without a change
// here.

const ARRAY_ELEMENT = /^(.*)\.(\d+)$/;

// "current.3" -> {base: "current", index: 3}; a plain key -> {base: key, index: -1}.
export function splitArrayKey(key) {
  const match = ARRAY_ELEMENT.exec(key);
  return match ? { base: match[1], index: Number(match[2]) } : { base: key, index: -1 };
}

export class DisplayDictionary {
  constructor(json) {
    if (!json || !Array.isArray(json.packets)) {
      throw new Error('display dictionary: no "packets" array');
    }
    this.name = json.name || 'RSE rover';
    this.packets = new Map();
    for (const packet of json.packets) {
      const fields = (packet.fields || []).filter((f) => f && typeof f.key === 'string');
      this.packets.set(packet.name, {
        name: packet.name,
        apid: packet.apid,
        description: packet.description || '',
        fields,
        fieldByKey: new Map(fields.map((f) => [f.key, f]))
      });
    }
  }

  packetNames() {
    return [...this.packets.keys()];
  }

  packet(name) {
    return this.packets.get(name);
  }

  hasPacket(name) {
    return this.packets.has(name);
  }

  field(packetName, key) {
    return this.packets.get(packetName)?.fieldByKey.get(key);
  }

  // The element keys of an array field in index order ("current.0" ..), or
  // [key] when the packet has the field as a scalar, or [] when it has neither.
  arrayKeys(packetName, base) {
    const packet = this.packets.get(packetName);
    if (!packet) {
      return [];
    }
    if (packet.fieldByKey.has(base)) {
      return [base];
    }
    return packet.fields
      .map((f) => ({ key: f.key, ...splitArrayKey(f.key) }))
      .filter((k) => k.base === base && k.index >= 0)
      .sort((a, b) => a.index - b.index)
      .map((k) => k.key);
  }

  // Array bases of a packet with their element count: [{base, count}].
  arrays(packetName) {
    const packet = this.packets.get(packetName);
    const counts = new Map();
    for (const f of packet ? packet.fields : []) {
      const { base, index } = splitArrayKey(f.key);
      if (index >= 0) {
        counts.set(base, Math.max(counts.get(base) || 0, index + 1));
      }
    }
    return [...counts].map(([base, count]) => ({ base, count }));
  }
}

export async function loadDictionary(url = '/api/dictionary') {
  const response = await fetch(url);
  if (!response.ok) {
    throw new Error(`GET ${url}: HTTP ${response.status}`);
  }
  return new DisplayDictionary(await response.json());
}
