#!/usr/bin/env bash
# Proves the README's promise that `make test` works on a fresh Debian 12 machine:
# builds a minimal Debian 12 root with debootstrap, adds only `make`, clones this
# repository into it and runs `make test` there, so `make deps` must install
# everything else itself. Needs root and Debian's package archive; about 5 minutes.
# Not part of CI (CI's own machine is already a fresh clone on the base image).
#
# usage: sudo .ci/fresh_debian_check.sh [ROOT_DIR]   (default: a new temporary folder)
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
root=${1:-$(mktemp -d /tmp/rse-fresh-debian.XXXXXX)}
mirror=${DEBIAN_MIRROR:-http://deb.debian.org/debian}

command -v debootstrap >/dev/null || apt-get install -y -qq debootstrap
[ -x "$root/bin/bash" ] || debootstrap --variant=minbase bookworm "$root" "$mirror"
cleanup() { umount "$root/proc" "$root/dev" "$root/sys" 2>/dev/null || true; }
trap cleanup EXIT
mount -t proc proc "$root/proc"
mount --bind /dev "$root/dev"
mount -t sysfs sys "$root/sys"
cp /etc/resolv.conf "$root/etc/" 2>/dev/null || true
rm -rf "$root/root/rse"
git clone -q "$repo" "$root/root/rse"
chroot "$root" /bin/bash -c '
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq && apt-get install -y -qq make >/dev/null
  cd /root/rse && make test'
