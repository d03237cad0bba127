#!/usr/bin/awk -f
# Decodes a candump -L log against the CAN map of docs/icd.md §1.2. Every frame
# must be one the ICD lists, with the documented length, from a known node;
# anything else is printed as UNDECODED and makes the exit status 1.
# Output: one decoded line per frame, then a count per frame type. POSIX awk
# (mawk, gawk, busybox).
#   awk -f decode_candump.awk session.log
function hex(s,   i, v) { v = 0; s = toupper(s); for (i = 1; i <= length(s); i++) v = v * 16 + index("0123456789ABCDEF", substr(s, i, 1)) - 1; return v }
function hexbyte(s, i) { return hex(substr(s, 2 * i + 1, 2)) }
function u16(s, i) { return hexbyte(s, i) + 256 * hexbyte(s, i + 1) }
function s16(s, i,   v) { v = u16(s, i); return v >= 32768 ? v - 65536 : v }
function s32(s, i,   v) { v = u16(s, i) + 65536 * u16(s, i + 2); return v >= 2147483648 ? v - 4294967296 : v }
function drive(n) { return n >= 1 && n <= 6 }
function node(n) { return drive(n) || (n >= 32 && n <= 37) }
function ok(kind, text) { count[kind]++; printf "%s %-14s %s\n", time, kind, text }
function bad(why) { undecoded++; printf "%s UNDECODED      %s#%s (%s)\n", time, idhex, data, why }
{
  time = $1; split($3, part, "#"); idhex = part[1]; data = part[2]
  id = hex(idhex); dlc = length(data) / 2; n = id % 128; fn = id - n
  if (id == 0) {
    if (dlc != 2) { bad("NMT needs 2 bytes"); next }
    ok("NMT", sprintf("command 0x%02X node %d", hexbyte(data, 0), hexbyte(data, 1)))
  } else if (id == 128) {
    if (dlc != 0) { bad("SYNC has no data"); next }
    ok("SYNC", "")
  } else if (fn == 128) {
    if (!node(n) || dlc != 8) { bad("EMCY: unknown node or length"); next }
    ok("EMCY", sprintf("node %d code 0x%04X register 0x%02X", n, u16(data, 0), hexbyte(data, 2)))
  } else if (fn == 384) {
    if (!drive(n) || dlc != 8) { bad("TPDO1: unknown drive or length"); next }
    ok("TPDO1", sprintf("drive %d statusword 0x%04X velocity %d mrad/s current %d mA", n, u16(data, 0), s32(data, 2), s16(data, 6)))
  } else if (fn == 640) {
    if (!drive(n) || dlc != 2) { bad("TPDO2: unknown drive or length"); next }
    ok("TPDO2", sprintf("drive %d motor temperature %.1f degC", n, s16(data, 0) / 10))
  } else if (fn == 512) {
    if (!drive(n) || dlc != 6) { bad("RPDO1: unknown drive or length"); next }
    ok("RPDO1", sprintf("drive %d controlword 0x%04X target %d mrad/s", n, u16(data, 0), s32(data, 2)))
  } else if (fn == 1408 || fn == 1536) {
    if (!drive(n) || dlc != 8) { bad("SDO: unknown drive or length"); next }
    ok(fn == 1536 ? "SDO-request" : "SDO-response", sprintf("drive %d cs 0x%02X object 0x%04X:%d", n, hexbyte(data, 0), u16(data, 1), hexbyte(data, 3)))
  } else if (id >= 1696 && id <= 1700) {
    if (dlc != 8) { bad("device frame needs 8 bytes"); next }
    split("IMU POWER HAZARD FIX-X FIX-Y", dev, " ")
    ok(dev[id - 1695], "")
  } else if (id == 1701 || id == 1702) {
    if (dlc != 8) { bad("instrument report needs 8 bytes"); next }
    k = int(hexbyte(data, 0) / 16); s = hexbyte(data, 0) % 16
    if ((k != 1 && k != 2) || s > 3) { bad("instrument report kind or state"); next }
    ok(id == 1701 ? "GRINDER" : "CAMERA", sprintf("%s state %d command %d", k == 1 ? "status" : "refusal", s, u16(data, 3)))
  } else if (id == 1717 || id == 1718) {
    if (dlc != 8) { bad("instrument command needs 8 bytes"); next }
    ok(id == 1717 ? "GRINDER-CMD" : "CAMERA-CMD", sprintf("action %d target %d command %d", hexbyte(data, 0), hexbyte(data, 1), u16(data, 2)))
  } else if (id == 1728 || id == 1729) {
    if (dlc < 1 || dlc > 8) { bad("ISO-TP frame length"); next }
    ok(id == 1728 ? "ISOTP-uplink" : "ISOTP-downlink", sprintf("pci 0x%X", int(hexbyte(data, 0) / 16)))
  } else if (fn == 1792) {
    if (!node(n) || dlc != 1) { bad("heartbeat: unknown node or length"); next }
    s = hexbyte(data, 0)
    if (s != 0 && s != 4 && s != 5 && s != 127) { bad("heartbeat state byte"); next }
    ok("HEARTBEAT", sprintf("node 0x%02X state 0x%02X", n, s))
  } else {
    bad("COB-ID not in the ICD")
  }
}
END {
  for (k in count) printf "count %-14s %d\n", k, count[k]
  printf "frames %d, undecoded %d\n", NR, undecoded + 0
  exit undecoded > 0 ? 1 : 0
}
