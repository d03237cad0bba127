#!/bin/bash
# run_in_vm.sh — run a test script inside a small qemu VM (Debian's own kernel,
# software emulation) that has a real SocketCAN interface vcan0.
#
# usage: run_in_vm.sh [--bin FILE]... [--file FILE]... GUEST_SCRIPT [ARGS...]
#
# The host kernel here has no CAN; the guest kernel (linux-image-*-amd64 from the
# Debian archive) loads can, can-raw, can-dev, vcan, can-isotp, can-bcm, brings up
# vcan0, then runs GUEST_SCRIPT ARGS with busybox sh. The script's output goes to
# this script's stdout; its exit code becomes this script's exit code.
# README.md beside this file has the details (env variables, exit codes, timings).
set -euo pipefail

ME=run_in_vm
SCRIPT_DIR=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
REPO_ROOT=$(cd "$SCRIPT_DIR/../../.." && pwd)

VM_TIMEOUT=${VM_TIMEOUT:-300}
VM_CACHE=${VM_CACHE:-$REPO_ROOT/build/vcan_vm/cache}
VM_MEM=${VM_MEM:-512}
VM_SMP=${VM_SMP:-1}
VM_KEEP=${VM_KEEP:-0}
VM_VERBOSE=${VM_VERBOSE:-0}

# Exit codes of the harness itself (the guest script's own code passes through).
EX_USAGE=2
EX_SETUP=125     # a tool, package, download or module is missing; or the VM died
EX_TIMEOUT=124   # the VM did not finish within VM_TIMEOUT seconds

# Modules loaded in the guest, in this order (their depends= are added first).
# Required ones must exist; optional ones are loaded when the kernel ships them.
MODS_REQUIRED=(can can-raw can-dev vcan can-isotp)
MODS_OPTIONAL_LOAD=(can-bcm)
# Copied into the guest (/lib/modules/rse/) but not loaded: insmod them if needed
# (softdog: the watchdog test, unit_test/integration/watchdog_test/).
MODS_EXTRA=(can-gw can-j1939 vxcan softdog)
# The prepared kernel's cache folder is named with these lists, so a change to
# them prepares it again instead of reusing one without the new modules.
MODS_SIG=$(printf '%s ' "${MODS_REQUIRED[@]}" / "${MODS_OPTIONAL_LOAD[@]}" / "${MODS_EXTRA[@]}" | cksum | cut -d' ' -f1)

PACKAGES=(qemu-system-x86 busybox-static can-utils)

log()  { echo "$ME: $*" >&2; }
vlog() { if [ "$VM_VERBOSE" = 1 ]; then log "$@"; fi; }
die()  { local code=$1; shift; echo "$ME: error: $*" >&2; exit "$code"; }

usage() {
    cat >&2 <<'EOF'
usage: run_in_vm.sh [--bin FILE]... [--file FILE]... GUEST_SCRIPT [ARGS...]
  --bin FILE    copy an x86_64 executable to /opt/rse/bin/<basename> in the guest,
                with every shared library ldd lists (same absolute paths) (repeatable)
  --file FILE   copy a data file to /opt/rse/data/<basename> (repeatable)
  GUEST_SCRIPT  POSIX sh script run by busybox sh in the guest, with ARGS, after
                the CAN modules are loaded and vcan0 is up
env: VM_TIMEOUT (s, default 300), VM_CACHE (default build/vcan_vm/cache),
     VM_MEM (MiB, default 512), VM_SMP (default 1), VM_KEEP=1 (keep the work dir),
     VM_VERBOSE=1 (more host-side messages)
exit: the guest script's exit code; 124 VM timed out; 125 setup failed or the VM
      died without a result; 2 bad command line
EOF
}

# ---------------------------------------------------------------------------
# Command line.
BINS=()
FILES=()
while [ $# -gt 0 ]; do
    case "$1" in
        --bin)  [ $# -ge 2 ] || { usage; exit $EX_USAGE; }; BINS+=("$2"); shift 2 ;;
        --bin=*) BINS+=("${1#--bin=}"); shift ;;
        --file) [ $# -ge 2 ] || { usage; exit $EX_USAGE; }; FILES+=("$2"); shift 2 ;;
        --file=*) FILES+=("${1#--file=}"); shift ;;
        -h|--help) usage; exit 0 ;;
        --) shift; break ;;
        -*) log "unknown option: $1"; usage; exit $EX_USAGE ;;
        *) break ;;
    esac
done
[ $# -ge 1 ] || { usage; exit $EX_USAGE; }
GUEST_SCRIPT=$1; shift
GUEST_ARGS=("$@")

[ -f "$GUEST_SCRIPT" ] && [ -r "$GUEST_SCRIPT" ] || die $EX_USAGE "guest script not found: $GUEST_SCRIPT"
for f in ${BINS[@]+"${BINS[@]}"}; do
    [ -f "$f" ] && [ -r "$f" ] || die $EX_USAGE "--bin: no such file: $f"
done
for f in ${FILES[@]+"${FILES[@]}"}; do
    [ -f "$f" ] && [ -r "$f" ] || die $EX_USAGE "--file: no such file: $f"
done
case "$VM_TIMEOUT" in ''|*[!0-9]*) die $EX_USAGE "VM_TIMEOUT must be a whole number of seconds: $VM_TIMEOUT" ;; esac
case "$VM_MEM" in ''|*[!0-9]*) die $EX_USAGE "VM_MEM must be a number of MiB: $VM_MEM" ;; esac
case "$VM_SMP" in ''|*[!0-9]*|0) die $EX_USAGE "VM_SMP must be a positive number: $VM_SMP" ;; esac

[ "$(uname -m)" = x86_64 ] || die $EX_SETUP "this harness runs on x86_64 hosts only (found $(uname -m))"

# ---------------------------------------------------------------------------
# Host tools and Debian packages (installed only when missing).
for t in dpkg-query apt-get apt-cache dpkg-deb ldd gzip timeout flock find sed od mktemp; do
    command -v "$t" >/dev/null 2>&1 || die $EX_SETUP "required host tool missing: $t"
done

SUDO=
if [ "$(id -u)" != 0 ]; then SUDO=$(command -v sudo || true); fi

# apt's own output goes to a log; it is shown only when apt fails.
APT_LOG=$(mktemp /tmp/run_in_vm.apt.XXXXXX)
trap 'rm -f "$APT_LOG"' EXIT
apt_failed() { tail -n 15 "$APT_LOG" >&2; die $EX_SETUP "$*"; }
APT_UPDATED=0
apt_update() {
    if [ "$APT_UPDATED" = 0 ]; then
        log "apt-get update"
        ${SUDO:+"$SUDO"} apt-get -o DPkg::Lock::Timeout=300 update -qq >>"$APT_LOG" 2>&1 \
            || apt_failed "apt-get update failed"
        APT_UPDATED=1
    fi
}
need_root() {
    if [ "$(id -u)" != 0 ] && [ -z "$SUDO" ]; then
        die $EX_SETUP "$1: run as root (or install sudo)"
    fi
}
pkg_installed() {
    [ "$(dpkg-query -W -f='${db:Status-Status}' "$1" 2>/dev/null || true)" = installed ]
}

# Install the packages "$@" that are not installed yet (nothing to do: no apt call).
ensure_pkgs() {
    local p missing=() install_cmd
    for p in "$@"; do pkg_installed "$p" || missing+=("$p"); done
    [ ${#missing[@]} -gt 0 ] || return 0
    need_root "packages missing (${missing[*]})"
    log "installing: ${missing[*]}"
    install_cmd=()
    if [ -n "$SUDO" ]; then install_cmd+=("$SUDO"); fi
    install_cmd+=(env DEBIAN_FRONTEND=noninteractive apt-get -o DPkg::Lock::Timeout=300
                  install -y -qq --no-install-recommends "${missing[@]}")
    if ! "${install_cmd[@]}" >>"$APT_LOG" 2>&1; then
        apt_update      # stale or missing package lists: update once and retry
        "${install_cmd[@]}" >>"$APT_LOG" 2>&1 || apt_failed "apt-get install ${missing[*]} failed"
    fi
    log "installed: ${missing[*]}"
}
ensure_pkgs "${PACKAGES[@]}"
QEMU=$(command -v qemu-system-x86_64 || true)
[ -n "$QEMU" ] || die $EX_SETUP "qemu-system-x86_64 not found after installing qemu-system-x86"
BUSYBOX=/bin/busybox
[ -x "$BUSYBOX" ] || die $EX_SETUP "$BUSYBOX not found (package busybox-static)"

# ---------------------------------------------------------------------------
# The kernel: linux-image-<abi>-amd64, resolved through linux-image-amd64, downloaded
# once into $VM_CACHE and reduced there to vmlinuz + the CAN modules (uncompressed).
mkdir -p "$VM_CACHE/debs" "$VM_CACHE/kernel" || die $EX_SETUP "cannot create cache dir $VM_CACHE"
VM_CACHE=$(cd "$VM_CACHE" && pwd)

# Debian's container images switch apt's binary cache off (docker-clean), which makes
# each apt-cache call re-read every list (~1.3 s); keep a private one in the cache dir.
APT_CACHE_OPTS=(-o "Dir::Cache::pkgcache=$VM_CACHE/apt/pkgcache.bin"
                -o "Dir::Cache::srcpkgcache=$VM_CACHE/apt/srcpkgcache.bin")
mkdir -p "$VM_CACHE/apt"
resolve_kernel_pkg() {
    { apt-cache "${APT_CACHE_OPTS[@]}" depends linux-image-amd64 2>/dev/null || true; } \
        | sed -n 's/^ *Depends: *\(linux-image-[0-9][^ ]*-amd64\) *$/\1/p' | head -n 1
}
candidate_version() {
    { apt-cache "${APT_CACHE_OPTS[@]}" policy "$1" 2>/dev/null || true; } | sed -n 's/^ *Candidate: *//p' | head -n 1
}
can_apt_update() { [ "$(id -u)" = 0 ] || [ -n "$SUDO" ]; }

# Newest kernel already prepared in the cache (fallback when apt cannot resolve).
newest_cached_kernel() {
    local d best=
    for d in "$VM_CACHE"/kernel/*_m"$MODS_SIG"/READY; do
        [ -e "$d" ] || continue
        best=$(dirname "$d")
    done
    [ -n "$best" ] && echo "$best"
}

# Extract the module named $1 (dashes and underscores equivalent) from the unpacked
# tree index into $2/<name>.ko, decompressing .xz/.zst/.gz. Prints nothing.
declare -A MOD_PATH=()
index_modules() {   # $1 = lib/modules/<ver>/kernel
    local f b n
    while IFS= read -r f; do
        b=${f##*/}
        b=${b%.xz}; b=${b%.zst}; b=${b%.gz}; b=${b%.ko}
        n=${b//-/_}
        MOD_PATH[$n]=$f
    done < <(find "$1" -type f \( -name '*.ko' -o -name '*.ko.xz' -o -name '*.ko.zst' -o -name '*.ko.gz' \))
}
extract_module() {  # $1 = module name, $2 = dest dir; sets EXTRACTED name
    local n=${1//-/_} src dst
    src=${MOD_PATH[$n]:-}
    [ -n "$src" ] || return 1
    dst="$2/${1//_/-}.ko"
    case "$src" in
        *.ko)     cp "$src" "$dst" ;;
        *.ko.xz)  command -v xz >/dev/null || ensure_pkgs xz-utils    # busybox insmod reads no .xz
                  xz -dc "$src" > "$dst" ;;
        *.ko.zst) command -v zstd >/dev/null || ensure_pkgs zstd
                  zstd -qdc "$src" > "$dst" ;;
        *.ko.gz)  gzip -dc "$src" > "$dst" ;;
    esac
}
mod_depends() {     # $1 = .ko file: its depends= list, space separated
    tr '\0' '\n' < "$1" | sed -n 's/^depends=//p' | head -n 1 | tr ',' ' '
}

# Add module $1 and (first) its dependencies to LOAD_ORDER, extracting into $2.
declare -A MOD_DONE=()
LOAD_ORDER=()
add_module() {      # $1 name, $2 dest dir, $3 chain (cycle guard)
    local name=${1//_/-} key=${1//-/_} dep
    [ -z "${MOD_DONE[$key]:-}" ] || return 0
    case " $3 " in *" $key "*) die $EX_SETUP "module dependency cycle: $3 $key" ;; esac
    extract_module "$name" "$2" || return 1
    for dep in $(mod_depends "$2/$name.ko"); do
        add_module "$dep" "$2" "$3 $key" || die $EX_SETUP "module $dep (needed by $name) missing in the kernel package"
    done
    MOD_DONE[$key]=1
    LOAD_ORDER+=("$name")
}

download_deb() {    # $1 pkg, $2 version: path of the .deb in $VM_CACHE/debs (downloads if absent)
    local pkg=$1 ver=$2 deb dl
    deb=$(find "$VM_CACHE/debs" -maxdepth 1 -name "${pkg}_${ver//:/%3a}_amd64.deb" | head -n 1)
    if [ -n "$deb" ]; then vlog "kernel package cached: $deb"; echo "$deb"; return 0; fi
    log "downloading $pkg ($ver) into $VM_CACHE/debs"
    dl=$(mktemp -d "$VM_CACHE/debs/.dl.XXXXXX")
    if ! (cd "$dl" && apt-get -o APT::Sandbox::User=root -qq download "$pkg=$ver" >>"$APT_LOG" 2>&1); then
        tail -n 5 "$APT_LOG" >&2
        rm -rf "$dl"; return 1
    fi
    deb=$(find "$dl" -maxdepth 1 -name '*.deb' | head -n 1)
    if [ -z "$deb" ]; then rm -rf "$dl"; return 1; fi
    mv "$deb" "$VM_CACHE/debs/"
    rm -rf "$dl"
    echo "$VM_CACHE/debs/${deb##*/}"
}

prepare_kernel() {  # $1 package name; sets KDIR=$VM_CACHE/kernel/<pkg>_<ver>/ (READY)
    local pkg=$1 ver deb kdir stage tree kver vmlinuz m
    ver=$(candidate_version "$pkg")
    if [ -z "$ver" ] || [ "$ver" = "(none)" ]; then
        die $EX_SETUP "apt-cache knows no candidate version of $pkg"
    fi
    kdir="$VM_CACHE/kernel/${pkg}_${ver}_m${MODS_SIG}"
    if [ -e "$kdir/READY" ]; then KDIR=$kdir; return 0; fi
    # leftovers of an interrupted earlier run (we hold the cache lock)
    rm -rf "$VM_CACHE"/debs/.dl.* "$VM_CACHE"/kernel/.stage.* "$VM_CACHE"/kernel/*.tmp

    if ! deb=$(download_deb "$pkg" "$ver"); then
        # Stale package lists can name a file the archive no longer has: update once.
        if [ "$APT_UPDATED" = 1 ] || ! can_apt_update; then
            die $EX_SETUP "apt-get download $pkg=$ver failed"
        fi
        apt_update
        pkg=$(resolve_kernel_pkg)
        [ -n "$pkg" ] || die $EX_SETUP "cannot resolve linux-image-amd64 after apt-get update"
        case "$pkg" in *-cloud-*|*-rt-*) die $EX_SETUP "resolved kernel $pkg is a cloud/rt flavour" ;; esac
        ver=$(candidate_version "$pkg")
        kdir="$VM_CACHE/kernel/${pkg}_${ver}_m${MODS_SIG}"
        if [ -e "$kdir/READY" ]; then KDIR=$kdir; return 0; fi
        deb=$(download_deb "$pkg" "$ver") || die $EX_SETUP "apt-get download $pkg=$ver failed"
    fi

    log "unpacking ${deb##*/}"
    stage=$(mktemp -d "$VM_CACHE/kernel/.stage.XXXXXX")
    rm -rf "$kdir"; mkdir -p "$kdir.tmp/modules"
    if ! dpkg-deb -x "$deb" "$stage/x"; then
        rm -rf "$stage" "$kdir.tmp" "$deb"
        die $EX_SETUP "dpkg-deb -x $deb failed (corrupt download? removed it; the next run downloads it again)"
    fi
    vmlinuz=$(find "$stage/x/boot" -maxdepth 1 -name 'vmlinuz-*' | head -n 1)
    [ -n "$vmlinuz" ] || { rm -rf "$stage" "$kdir.tmp"; die $EX_SETUP "no boot/vmlinuz-* in $deb"; }
    kver=${vmlinuz##*/vmlinuz-}
    tree="$stage/x/lib/modules/$kver/kernel"
    [ -d "$tree" ] || tree=$(find "$stage/x" -type d -path "*/lib/modules/$kver/kernel" | head -n 1)
    [ -n "$tree" ] && [ -d "$tree" ] || { rm -rf "$stage" "$kdir.tmp"; die $EX_SETUP "no lib/modules/$kver/kernel in $deb"; }
    cp "$vmlinuz" "$kdir.tmp/vmlinuz"
    index_modules "$tree"
    for m in "${MODS_REQUIRED[@]}"; do
        add_module "$m" "$kdir.tmp/modules" "" \
            || { rm -rf "$stage" "$kdir.tmp"; die $EX_SETUP "required module $m missing in $pkg"; }
    done
    for m in "${MODS_OPTIONAL_LOAD[@]}"; do
        add_module "$m" "$kdir.tmp/modules" "" || log "note: optional module $m not in $pkg"
    done
    printf '%s\n' "${LOAD_ORDER[@]}" > "$kdir.tmp/load.order"
    for m in "${MODS_EXTRA[@]}"; do
        LOAD_ORDER=()
        add_module "$m" "$kdir.tmp/modules" "" || vlog "note: extra module $m not in $pkg"
    done
    echo "$kver" > "$kdir.tmp/kernel.release"
    rm -rf "$stage"
    touch "$kdir.tmp/READY"
    mv "$kdir.tmp" "$kdir"
    KDIR=$kdir
}

KDIR=
exec 9>"$VM_CACHE/.lock"
flock 9 || die $EX_SETUP "cannot lock $VM_CACHE/.lock"
KPKG=$(resolve_kernel_pkg)
if [ -z "$KPKG" ] && can_apt_update; then
    # No package lists yet (fresh machine): update once and retry.
    apt_update
    KPKG=$(resolve_kernel_pkg)
fi
if [ -z "$KPKG" ]; then
    KDIR=$(newest_cached_kernel || true)
    [ -n "$KDIR" ] || die $EX_SETUP "cannot resolve the kernel: 'apt-cache depends linux-image-amd64' names no linux-image-*-amd64"
    log "note: apt cannot resolve linux-image-amd64; using cached $(basename "$KDIR")"
else
    case "$KPKG" in
        *-cloud-*|*-rt-*) die $EX_SETUP "resolved kernel $KPKG is a cloud/rt flavour (no CAN modules)" ;;
    esac
    prepare_kernel "$KPKG"
fi
flock -u 9
exec 9>&-
KREL=$(cat "$KDIR/kernel.release")
vlog "kernel $KREL from $KDIR"

# ---------------------------------------------------------------------------
# Work dir and clean-up (no mounts are made; the only child process is qemu).
mkdir -p "$REPO_ROOT/build/vcan_vm"
WORK=$(mktemp -d "$REPO_ROOT/build/vcan_vm/run.XXXXXX")
TIMEOUT_PID=
# shellcheck disable=SC2317  # called through trap
cleanup() {
    local rc=$?
    if [ -n "$TIMEOUT_PID" ] && kill -0 "$TIMEOUT_PID" 2>/dev/null; then
        kill -TERM "$TIMEOUT_PID" 2>/dev/null || true
        sleep 1
        kill -KILL "$TIMEOUT_PID" 2>/dev/null || true
    fi
    if [ -f "$WORK/qemu.pid" ]; then
        local qp; qp=$(cat "$WORK/qemu.pid" 2>/dev/null || true)
        if [ -n "$qp" ] && kill -0 "$qp" 2>/dev/null; then kill -KILL "$qp" 2>/dev/null || true; fi
    fi
    rm -f "$APT_LOG"
    if [ "$VM_KEEP" = 1 ]; then log "work dir kept: $WORK"; else rm -rf "$WORK"; fi
    exit "$rc"
}
trap cleanup EXIT
trap 'log "interrupted"; exit 130' INT
trap 'log "terminated"; exit 143' TERM

ROOT="$WORK/root"
mkdir -p "$ROOT"/usr/bin "$ROOT"/usr/sbin "$ROOT"/usr/lib "$ROOT"/usr/lib64
ln -s usr/bin "$ROOT/bin"; ln -s usr/sbin "$ROOT/sbin"
ln -s usr/lib "$ROOT/lib"; ln -s usr/lib64 "$ROOT/lib64"
mkdir -p "$ROOT"/proc "$ROOT"/sys "$ROOT"/dev "$ROOT"/tmp "$ROOT"/run "$ROOT"/etc \
         "$ROOT"/root "$ROOT"/opt/rse/bin "$ROOT"/opt/rse/data "$ROOT"/opt/rse/test \
         "$ROOT"/lib/modules/rse
printf 'root:x:0:0:root:/root:/bin/sh\n' > "$ROOT/etc/passwd"
printf 'root:x:0:\n' > "$ROOT/etc/group"
printf '127.0.0.1 localhost\n::1 localhost\n' > "$ROOT/etc/hosts"
echo rse-vm > "$ROOT/etc/hostname"

# Copy a host file to the same absolute path inside the guest root.
copy_same_path() {
    local src=$1 dst="$ROOT$1"
    [ -e "$dst" ] && return 0
    mkdir -p "${dst%/*}"
    cp -L "$src" "$dst"
}

# ELF class of file $1: "x86_64", "other" (another ELF) or "none" (not ELF): one od call.
elf_kind() {
    local -a h
    read -r -a h < <(od -An -tu1 -N20 -w20 "$1" 2>/dev/null || true)
    if [ "${#h[@]}" -lt 20 ] || [ "${h[0]}" != 127 ] || [ "${h[1]}" != 69 ] \
       || [ "${h[2]}" != 76 ] || [ "${h[3]}" != 70 ]; then
        echo none
    elif [ "${h[4]}" = 2 ] && [ "${h[18]}" = 62 ] && [ "${h[19]}" = 0 ]; then
        echo x86_64          # ELFCLASS64, e_machine EM_X86_64 (little endian)
    else
        echo other
    fi
}

# Copy the shared libraries (and the loader) of the host executables "$@" into the
# guest at their own absolute paths: one ldd call for all of them.
copy_libs() {
    local out line lib cur=$1
    out=$(ldd "$@" 2>&1 || true)
    while IFS= read -r line; do
        if [ $# -gt 1 ] && [[ "$line" == /*: ]]; then cur=${line%:}; continue; fi
        case "$line" in
            *"not a dynamic executable"*|*"statically linked"*) continue ;;
            *"=> not found"*) lib=${line%% =>*}; lib=${lib#"${lib%%[![:space:]]*}"}
                              die $EX_SETUP "$cur needs a library the host lacks: $lib" ;;
            *"=> /"*) lib=${line#*=> }; lib=${lib%% (*} ;;
            *"=>"*) continue ;;                    # linux-vdso etc. (no file)
            [[:space:]]/*) lib=${line#"${line%%[![:space:]]*}"}; lib=${lib%% (*} ;;
            *"ldd: "*|*"error"*) die $EX_SETUP "ldd $cur: $line" ;;
            *) continue ;;
        esac
        [ -e "$lib" ] || die $EX_SETUP "$cur: ldd names $lib but it does not exist"
        copy_same_path "$lib"
    done <<< "$out"
}

# Copy host executables into the guest (dst dir $1, then files). ELF files must be
# x86_64; their libraries come along. Non-ELF files (scripts) are copied as they are.
add_bins() {
    local dir=$1 f elf=() dst=(); shift
    mkdir -p "$ROOT$dir"
    for f in "$@"; do
        case "$(elf_kind "$f")" in
            x86_64) elf+=("$f") ;;
            other) die $EX_USAGE "$f is an ELF file but not for x86_64" ;;
        esac
        dst+=("$ROOT$dir/${f##*/}")
    done
    cp -L "$@" "$ROOT$dir/"
    chmod 0755 "${dst[@]}"
    [ ${#elf[@]} -eq 0 ] || copy_libs "${elf[@]}"
}

# busybox and its applets (flat in /usr/bin; /bin and /sbin link there)
cp "$BUSYBOX" "$ROOT/usr/bin/busybox"
"$BUSYBOX" --install -s "$ROOT/usr/bin" || die $EX_SETUP "busybox --install failed"
if [ "$(readlink "$ROOT/usr/bin/sh")" != /usr/bin/busybox ]; then
    # the links name the host's busybox path: point them at the guest's copy
    for a in $(cd "$ROOT/usr/bin" && find . -maxdepth 1 -type l -printf '%f\n'); do
        ln -sfn /usr/bin/busybox "$ROOT/usr/bin/$a"
    done
fi
[ "$(readlink "$ROOT/usr/bin/sh")" = /usr/bin/busybox ] || die $EX_SETUP "busybox applet links missing"

# can-utils: every binary the package ships, at the same paths as on the host
mapfile -t CAN_BINS < <(dpkg-query -L can-utils | grep -E '^/usr/bin/[^/]+$' || true)
CAN_OK=()
for f in "${CAN_BINS[@]}"; do [ -f "$f" ] && [ -x "$f" ] && CAN_OK+=("$f"); done
[ ${#CAN_OK[@]} -gt 0 ] || die $EX_SETUP "can-utils is installed but ships no binaries in /usr/bin"
for f in "${CAN_OK[@]}"; do rm -f "$ROOT$f"; done   # replace any busybox applet of that name
add_bins /usr/bin "${CAN_OK[@]}"
for t in candump cansend cangen isotpsend isotprecv; do
    [ -x "$ROOT/usr/bin/$t" ] || die $EX_SETUP "can-utils binary $t missing"
done

# glibc dlopen()s libgcc_s for pthread_cancel/pthread_exit and C++ unwinding:
# include it even when ldd does not list it.
for l in /lib/x86_64-linux-gnu/libgcc_s.so.1 /usr/lib/x86_64-linux-gnu/libgcc_s.so.1; do
    if [ -e "$l" ]; then copy_same_path "$l"; break; fi
done

# caller's binaries and data
declare -A SEEN=()
for f in ${BINS[@]+"${BINS[@]}"}; do
    b=${f##*/}
    [ -z "${SEEN[bin/$b]:-}" ] || die $EX_USAGE "two --bin files named $b"
    SEEN[bin/$b]=1
done
[ ${#BINS[@]} -eq 0 ] || add_bins /opt/rse/bin "${BINS[@]}"
for f in ${FILES[@]+"${FILES[@]}"}; do
    b=${f##*/}
    [ -z "${SEEN[data/$b]:-}" ] || die $EX_USAGE "two --file files named $b"
    SEEN[data/$b]=1
    cp -L "$f" "$ROOT/opt/rse/data/$b"
done

# modules
cp "$KDIR"/modules/*.ko "$ROOT/lib/modules/rse/"
cp "$KDIR/load.order" "$ROOT/lib/modules/rse/load.order"

# the test script and the command line that runs it (args single-quoted for sh)
TEST_NAME=$(basename "$GUEST_SCRIPT")
cp "$GUEST_SCRIPT" "$ROOT/opt/rse/test/$TEST_NAME"
chmod 0755 "$ROOT/opt/rse/test/$TEST_NAME"
sq() { local s=$1; printf "'%s'" "${s//\'/\'\\\'\'}"; }
{
    printf '#!/bin/sh\n# generated by run_in_vm.sh\nexec sh %s' "$(sq "/opt/rse/test/$TEST_NAME")"
    for a in ${GUEST_ARGS[@]+"${GUEST_ARGS[@]}"}; do printf ' %s' "$(sq "$a")"; done
    printf '\n'
} > "$ROOT/opt/rse/run_test.sh"
chmod 0755 "$ROOT/opt/rse/run_test.sh"

# A per-run token makes the result line unambiguous (a test cannot forge it by accident).
TOKEN=$(od -An -tx1 -N6 /dev/urandom | tr -d ' \n')
cat > "$ROOT/init" <<EOF
#!/bin/sh
# /init of the run_in_vm.sh guest (generated)
export PATH=/opt/rse/bin:/usr/local/bin:/usr/bin:/usr/sbin
export HOME=/root TMPDIR=/tmp RSE_BIN=/opt/rse/bin RSE_DATA=/opt/rse/data
setup_fail() {
    echo "RSE-VM-SETUP-FAILED $TOKEN \$*"
    sleep 1
    poweroff -f
}
mount -t proc proc /proc || setup_fail "mount proc"
mount -t sysfs sysfs /sys || setup_fail "mount sysfs"
mount -t devtmpfs devtmpfs /dev || setup_fail "mount devtmpfs"
mkdir -p /dev/pts /dev/shm
mount -t devpts devpts /dev/pts || setup_fail "mount devpts"
mount -t tmpfs -o mode=1777 tmpfs /dev/shm || setup_fail "mount /dev/shm"
mount -t tmpfs -o mode=1777 tmpfs /tmp || setup_fail "mount /tmp"
mount -t tmpfs -o mode=0755 tmpfs /run || setup_fail "mount /run"
hostname rse-vm
ip link set lo up || setup_fail "ip link set lo up"
for m in \$(cat /lib/modules/rse/load.order); do
    [ -f /lib/modules/rse/\$m.ko ] || setup_fail "module \$m.ko missing from the initramfs"
    insmod /lib/modules/rse/\$m.ko || setup_fail "insmod \$m.ko failed"
done
ip link add dev vcan0 type vcan || setup_fail "ip link add vcan0"
ip link set vcan0 up || setup_fail "ip link set vcan0 up"
echo "RSE-VM-READY $TOKEN kernel=\$(uname -r) modules=\$(cat /lib/modules/rse/load.order | tr '\n' ',' | sed 's/,\$//')"
cd /tmp
/opt/rse/run_test.sh < /dev/null
rc=\$?
# stop whatever the test left running, so nothing writes over the result line
if kill -s TERM -1 2>/dev/null; then
    sleep 0.2
    kill -s KILL -1 2>/dev/null
fi
echo "RSE-VM-RESULT rc=\$rc $TOKEN"
# a short margin for the UART to drain the last lines before the power goes
# (measured: 400 lines then the result line arrived complete without it)
sleep 0.1
poweroff -f
EOF
chmod 0755 "$ROOT/init"

(cd "$ROOT" && find . | "$BUSYBOX" cpio -o -H newc 2>/dev/null | gzip -1 > "$WORK/initrd.gz") \
    || die $EX_SETUP "packing the initramfs failed"
vlog "initramfs $(du -k "$WORK/initrd.gz" | cut -f1) KiB"

# ---------------------------------------------------------------------------
# Boot. TCG only (no -enable-kvm: KVM guests hung on these machines). No NIC.
QEMU_ARGS=(-m "$VM_MEM" -kernel "$KDIR/vmlinuz" -initrd "$WORK/initrd.gz"
           -append "console=ttyS0 quiet panic=-1"
           -nographic -no-reboot -nic none -pidfile "$WORK/qemu.pid")
[ "$VM_SMP" = 1 ] || QEMU_ARGS+=(-smp "$VM_SMP")

LOG="$WORK/console.log"
: > "$LOG"
log "booting $KREL (timeout ${VM_TIMEOUT}s)"
T0=$(date +%s.%N)
set +e
{
    timeout -k 5 "$VM_TIMEOUT" "$QEMU" "${QEMU_ARGS[@]}" < /dev/null 2>&1 &
    echo $! > "$WORK/timeout.pid"
    wait $!
    echo $? > "$WORK/qemu.rc"
} | sed -u -e 's/\r$//' -e 's/\x1b\[[0-9;?]*[A-Za-z]//g' -e 's/\x1b[c78]//g' -e 's/\r/\n/g' | tee "$LOG" &
PIPE_PID=$!
# timeout.pid is written at once; read it so the trap can stop the VM
for _ in 1 2 3 4 5 6 7 8 9 10; do
    [ -s "$WORK/timeout.pid" ] && break
    sleep 0.1
done
TIMEOUT_PID=$(cat "$WORK/timeout.pid" 2>/dev/null || true)
wait "$PIPE_PID"
set -e
T1=$(date +%s.%N)
TIMEOUT_PID=
QRC=$(cat "$WORK/qemu.rc" 2>/dev/null || echo "?")
ELAPSED=$(awk -v a="$T0" -v b="$T1" 'BEGIN { printf "%.1f", b - a }')
CONSOLE_LOG="$REPO_ROOT/build/vcan_vm/last_console.log"
cp "$LOG" "$CONSOLE_LOG" 2>/dev/null || true

# ---------------------------------------------------------------------------
# Result.
# Markers are matched anywhere in a line (a test's last line may lack its newline);
# the per-run token keeps them unambiguous.
if grep -q "RSE-VM-SETUP-FAILED $TOKEN" "$LOG"; then
    msg=$(sed -n "s/.*RSE-VM-SETUP-FAILED $TOKEN //p" "$LOG" | head -n 1)
    die $EX_SETUP "guest setup failed: $msg (console: $CONSOLE_LOG)"
fi
RESULT=$(sed -n "s/.*RSE-VM-RESULT rc=\([0-9][0-9]*\) $TOKEN\$/\1/p" "$LOG" | tail -n 1)
if [ -n "$RESULT" ]; then
    log "guest script exited $RESULT (VM ${ELAPSED}s)"
    exit "$RESULT"
fi
if [ "$QRC" = 124 ] || [ "$QRC" = 137 ]; then
    die $EX_TIMEOUT "VM timed out after ${VM_TIMEOUT}s without a result line (raise VM_TIMEOUT?; console: $CONSOLE_LOG)"
fi
if ! grep -q "RSE-VM-READY $TOKEN" "$LOG"; then
    die $EX_SETUP "VM stopped (qemu exit $QRC) before the guest was ready (console: $CONSOLE_LOG)"
fi
if grep -q 'Kernel panic' "$LOG"; then
    die $EX_SETUP "guest kernel panicked ($(grep -m1 -o 'Kernel panic.*' "$LOG")) before the result line (console: $CONSOLE_LOG)"
fi
die $EX_SETUP "VM stopped (qemu exit $QRC) without a result line: guest crashed or powered off early (console: $CONSOLE_LOG)"
