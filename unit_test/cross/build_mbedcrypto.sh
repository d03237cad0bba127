#!/usr/bin/env bash
# Builds mbedTLS's libmbedcrypto.a (rse-fsw's HMAC-SHA-256) for a cross target
# that Debian has no port for, hence no libmbedtls-dev of (powerpc): from
# Debian's own source package, the version the host has installed, configured
# with the host's Debian config.h so that the headers the flight code compiles
# against describe the library it links. The source comes through apt-get
# source with a package list of its own under build/ (the deb-src twins of the
# system's deb sources): the system's apt configuration is not touched.
# Run by make (docs/cross_targets.md); a few seconds once downloaded.
#
# usage: build_mbedcrypto.sh CROSS_PREFIX OUT_LIB   (e.g. powerpc-linux-gnu- build/powerpc/mbedtls/libmbedcrypto.a)
set -euo pipefail
prefix=$1 out=$2
root=$(pwd)/build/src
apt_dir=$root/apt
version=$(dpkg-query -W -f='${source:Version}' "libmbedtls-dev:$(dpkg --print-architecture)")
upstream=${version%-*}
src=$root/mbedtls-$upstream

if [ ! -d "$src" ]; then
  mkdir -p "$apt_dir/lists/partial" "$apt_dir/sources.list.d"
  : >"$apt_dir/sources.list"
  [ -f /etc/apt/sources.list ] && sed -n 's/^deb /deb-src /p' /etc/apt/sources.list >"$apt_dir/sources.list"
  for f in /etc/apt/sources.list.d/*.sources; do
    [ -e "$f" ] || continue
    sed 's/^Types: *deb *$/Types: deb-src/' "$f" >"$apt_dir/sources.list.d/$(basename "$f")"
  done
  apt_opts=(-o "Dir::Etc::SourceList=$apt_dir/sources.list" -o "Dir::Etc::SourceParts=$apt_dir/sources.list.d"
            -o "Dir::State::Lists=$apt_dir/lists" -o "APT::Sandbox::User=root")
  apt-get "${apt_opts[@]}" -qq update
  (cd "$root" && apt-get "${apt_opts[@]}" -qq source --download-only "mbedtls=$version")
  # The tarball's top folder is named after the upstream commit: strip it.
  mkdir -p "$src.tmp" && tar -xzf "$root/mbedtls_$upstream.orig.tar.gz" -C "$src.tmp" --strip-components=1
  [ -f "$src.tmp/library/Makefile" ] || { echo "build_mbedcrypto: no library/Makefile in the source package" >&2; exit 1; }
  mv "$src.tmp" "$src"
fi

# Debian's configuration of the same version (debian/rules sets options with
# scripts/config.py; the installed header is the result).
cp /usr/include/mbedtls/config.h "$src/include/mbedtls/config.h"
build=$root/mbedtls-build-${prefix%-}
rm -rf "$build" && cp -r "$src" "$build"
make -s -C "$build/library" CC="${prefix}gcc" AR="${prefix}ar" CFLAGS="-O2" libmbedcrypto.a
mkdir -p "$(dirname "$out")"
cp "$build/library/libmbedcrypto.a" "$out"
echo "build_mbedcrypto: $out from Debian's mbedtls $version source"
