// Archived telemetry from rse-ground serve: GET /api/history?packet=NAME&start=MS&end=MS
// answers the datums of that packet with start <= utc <= end, oldest first, at
// most 20 000 at a time and marked "truncated" when cut
// (docs/mission_control.md). A cut answer is followed by the next page from
// its last time, so a long interval comes back whole (up to MAX_PAGES pages).

const MAX_PAGES = 10;

// The datums of an answer: the contract's array, or an object holding it
// beside its "truncated" flag.
function datumsOf(body) {
  if (Array.isArray(body)) {
    return { datums: body, truncated: Boolean(body.truncated) };
  }
  if (body && typeof body === 'object') {
    const datums = body.datums || body.data || body.history || [];
    return { datums: Array.isArray(datums) ? datums : [], truncated: Boolean(body.truncated) };
  }
  return { datums: [], truncated: false };
}

export async function requestHistory(packet, start, end, { signal, url = '/api/history' } = {}) {
  const all = [];
  let from = Math.floor(start);
  const to = Math.ceil(end);
  let skipAtFrom = 0; // datums at time `from` already taken from the previous page
  for (let page = 0; page < MAX_PAGES; page++) {
    const query = new URLSearchParams({ packet, start: String(from), end: String(to) });
    const response = await fetch(`${url}?${query}`, { signal });
    if (!response.ok) {
      throw new Error(`GET ${url}?${query}: HTTP ${response.status}`);
    }
    const { datums, truncated } = datumsOf(await response.json());
    let skipped = 0;
    for (const datum of datums) {
      if (skipped < skipAtFrom && datum.utc === from) {
        skipped += 1;
        continue;
      }
      all.push(datum);
    }
    if (!truncated || datums.length === 0) {
      return all;
    }
    const last = datums[datums.length - 1].utc;
    skipAtFrom = datums.filter((d) => d.utc === last).length;
    from = last;
  }
  console.warn(`history of ${packet}: more than ${MAX_PAGES} pages, the rest left out`);
  return all;
}
