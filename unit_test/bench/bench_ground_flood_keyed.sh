#!/usr/bin/env bash
# make bench: the ground-link flood with well-formed NOOPs under the rover's own
# key id and a wrong MAC (bench_ground_flood --keyed), 40 000 packets/s: each
# costs rse-fsw a MAC at ingest and must take no queue slot from valid commands.
set -u
root=$(cd "$(dirname "$0")/../.." && pwd)
bin=${RSE_BIN_DIR:-$root/build/x86_64/bin}
exec "$bin/bench_ground_flood" --keyed --rate 40000 "$@"
