#!/usr/bin/env bash
# The simulator programs' command lines as a user meets them (docs/operations.md,
# "Command lines"): rse-sim, rse-demo and rse-montecarlo each print their usage
# on stdout and exit 0 for --help (and -h); a bad command line (an unknown
# option, a missing value, a value out of range, an unknown sub-command) exits
# 2 with one line on stderr naming the option and the value, then a line
# pointing to --help, and nothing on stdout. Host tools: no RSE_RUNNER.
# Ends with "N passed, N failed".
#
# env: RSE_BIN_DIR (where the programs are)
set -u
bin="${RSE_BIN_DIR:?set RSE_BIN_DIR}"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
passed=0 failed=0

check() {  # check NAME CONDITION-COMMAND...
  local name=$1; shift
  if "$@"; then passed=$((passed + 1)); echo "  pass: $name"
  else failed=$((failed + 1)); echo "  FAIL: $name"; fi
}

# help PROGRAM WORDS ARGS...: the usage on stdout naming WORDS, nothing on stderr, exit 0.
help() {
  local prog=$1 words=$2; shift 2
  "$bin/$prog" "$@" >"$work/out" 2>"$work/err"; local rc=$?
  check "$prog $*: exit 0" test "$rc" -eq 0
  check "$prog $*: the usage on stdout" grep -q -- "$words" "$work/out"
  check "$prog $*: nothing on stderr" test ! -s "$work/err"
}

# bad PROGRAM MESSAGE ARGS...: exit 2, "PROGRAM: MESSAGE" then the pointer to
# --help on stderr (two lines), nothing on stdout.
bad() {
  local prog=$1 message=$2; shift 2
  "$bin/$prog" "$@" >"$work/out" 2>"$work/err"; local rc=$?
  check "$prog $*: exit 2" test "$rc" -eq 2
  check "$prog $*: says '$message'" grep -qxF -- "$prog: $message" "$work/err"
  check "$prog $*: points to --help" sh -c "tail -n 1 '$work/err' | grep -qxF \"$prog: see '$prog --help'\""
  check "$prog $*: two lines on stderr" test "$(wc -l < "$work/err")" -eq 2
  check "$prog $*: nothing on stdout" test ! -s "$work/out"
}

echo "rse-sim"
help rse-sim "--coarse-map-source FILE" --help
help rse-sim "usage: rse-sim" -h
bad rse-sim "unknown or incomplete option '--no-such-option'" --no-such-option
bad rse-sim "option '--can' needs a value" --can
bad rse-sim "--time-scale '0' is not a whole factor 1..100" --can vcan0 --scenario x.toml --time-scale 0
bad rse-sim "--duration '5s' is not a positive number of seconds (at most 1e7)" --duration 5s --can vcan0 --scenario x.toml
bad rse-sim "--can and --scenario are required" --can vcan0
bad rse-sim "--coarse-map-source and --site-file: one at a time" --coarse-map-source a.toml --site-file a.toml
help rse-sim "--site-file FILE" --help
"$bin/rse-sim" --site-file sim_stub/scenarios/rock_field_100m.toml >"$work/out" 2>"$work/err"
check "rse-sim --site-file: the shipped 100 m site, byte for byte" cmp -s "$work/out" sim_stub/scenarios/sites/rock_field_100m.site
check "rse-sim --site-file: nothing on stderr" test ! -s "$work/err"
"$bin/rse-sim" --site-file no_such.toml >"$work/out" 2>"$work/err"; rc=$?
check "rse-sim --site-file of a scenario that does not load: exit 1" test "$rc" -eq 1
check "rse-sim --site-file of a scenario that does not load: says why" grep -q "no_such.toml: cannot open the file" "$work/err"

echo "rse-demo"
help rse-demo "--udp-commands \[ADDR:\]PORT" --help
help rse-demo "usage: rse-demo" -h
bad rse-demo "unknown or incomplete option '--no-such-option'" --no-such-option
bad rse-demo "option '--goto' needs a value" --goto
bad rse-demo "--pace '0.05' is not a factor over real time in [0.1, 1000] (1: real time; leave --pace out to run as fast as the CPU allows)" --pace 0.05
bad rse-demo "--duration '-3' is not a number of seconds in (0, 1e6]" --duration -3
bad rse-demo "unexpected argument 'extra' (rse-demo takes options only)" --quiet extra

echo "rse-montecarlo"
help rse-montecarlo "rse-montecarlo merge" --help
help rse-montecarlo "rse-montecarlo seed N" -h
help rse-montecarlo "MISSION: rse-demo's" run --help
bad rse-montecarlo "unknown or incomplete option '--no-such-option'" run --no-such-option
bad rse-montecarlo "unknown command 'fly' (run, block, merge or seed)" fly
bad rse-montecarlo "no command (run, block, merge or seed)"
bad rse-montecarlo "--jobs '0': 1..1024" run --jobs 0
bad rse-montecarlo "--goto '4,0,0.9': GOTO: risk=0.9 is out of range 1e-09..0.49 (expected <f64, 1e-09..0.49>)" run --goto 4,0,0.9
bad rse-montecarlo "block: --seeds, --block-size and --out are needed" block --seeds 1:4

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
