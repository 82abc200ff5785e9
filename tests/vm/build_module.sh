#!/usr/bin/env bash
# Builds a kernel module that Debian's kernel config leaves off (gpio-sim, vimc, ...) out of
# tree, from Debian's own kernel source (linux-source-X.Y) against the headers of the kernel
# the VM harness boots (linux-headers-<the /boot/vmlinuz-* version>), for tests/vm/ (issue #7,
# docs/gpio.md "Building gpio-sim"). Only the listed sources and the headers beside them are
# unpacked from the tarball; the .ko is cached in OUT_DIR and rebuilt only when the kernel, the
# source package, the file list or this script change.
#
# Usage: build_module.sh [-p PATCH]... OUT_DIR MODULE SOURCE.c [SOURCE.c...]
#   SOURCE paths are relative to the kernel tree (drivers/gpio/gpio-sim.c); they are linked
#   into one MODULE.ko, so a helper the kernel did not build in (kernel/irq/irq_sim.c, which
#   only a =y driver selects) can travel with the driver that needs it.
#   -p PATCH  applied with `patch -p1` in the unpacked tree (e.g. tests/vm/patches/*.patch)
# Prints the .ko's path as the last line. Exit 77 (the reason on stdout) when the source,
# headers or compiler are missing or do not match the kernel; 1 when the build fails.
# PROBELESS_VM_KERNEL picks another /boot/vmlinuz-*, as in run_in_vm.sh.
set -euo pipefail

usage() { echo "usage: $0 [-p PATCH]... OUT_DIR MODULE SOURCE.c..." >&2; exit 2; }
patches=()
while getopts "p:" opt; do
  case $opt in
    p) patches+=("$(realpath "$OPTARG")") ;; *) usage ;;
  esac
done
shift $((OPTIND - 1))
(($# >= 3)) || usage
out=$1 module=$2
shift 2
sources=("$@")

skip() { echo "SKIP: $*"; exit 77; }
kernel=${PROBELESS_VM_KERNEL:-$(ls -1 /boot/vmlinuz-* 2>/dev/null | sort -V | tail -1)}
[[ -n $kernel && -r $kernel ]] || skip "no readable /boot/vmlinuz-* (linux-image-amd64)"
kver=${kernel#/boot/vmlinuz-}
series=$(sed -E 's/^([0-9]+\.[0-9]+).*/\1/' <<<"$kver")
tarball=/usr/src/linux-source-$series.tar.xz
headers=/lib/modules/$kver/build

# The package versions: headers and source must come from the same upload as the image, since
# a driver may include private headers (gpio-sim: drivers/gpio/gpiolib.h) whose struct layouts
# must be the running kernel's, and MODVERSIONS checks every symbol's CRC at load.
pkg_version() { dpkg-query -W -f='${db:Status-Status} ${Version}' "$1" 2>/dev/null |
  sed -n 's/^installed //p'; }
image_version=$(pkg_version "linux-image-$kver")
[[ -n $image_version ]] || image_version=$(pkg_version "linux-image-$kver-unsigned")
[[ -n $image_version ]] || skip "kernel $kver is not from an installed linux-image-$kver package"
[[ -r $tarball ]] || skip "no $tarball (scripts/setup.sh installs linux-source-$series)"
[[ -r $headers/Makefile && -r $headers/Module.symvers ]] ||
  skip "no headers for $kver in $headers (scripts/setup.sh installs linux-headers-amd64)"
source_version=$(pkg_version "linux-source-$series")
headers_version=$(pkg_version "linux-headers-$kver")
[[ $headers_version == "$image_version" ]] ||
  skip "linux-headers-$kver is ${headers_version:-not installed}, the image is $image_version"
[[ $source_version == "$image_version" ]] ||
  skip "linux-source-$series is ${source_version:-not installed}, the image is $image_version"
for tool in make gcc patch; do
  command -v $tool >/dev/null || skip "no $tool (build-essential)"
done

mkdir -p "$out"
out=$(cd "$out" && pwd)
ko=$out/$module.ko
stamp=$out/$module.stamp
key="$kver $image_version $(cat "$0" "${patches[@]}" | sha256sum | cut -c1-16) ${sources[*]}"
if [[ -r $ko && -r $stamp && $(cat "$stamp") == "$key" ]]; then
  echo "cached: $ko (kernel $kver, $image_version)"
  echo "$ko"
  exit 0
fi

start=$(date +%s)
work=$out/$module.build
rm -rf "$work" "$ko" "$stamp"
mkdir -p "$work"
# One pass over the 140 MB tarball (xz cannot seek): each source, and the headers of its
# folder for its `#include "local.h"`.
top=linux-source-$series
# Each pattern once: tar reports a repeated one as not found.
declare -A patterns=()
for s in "${sources[@]}"; do
  [[ $s == *.c && $s != /* && $s != *..* ]] || { echo "FAIL: bad source path $s" >&2; exit 2; }
  patterns["$top/$s"]=1 patterns["$top/$(dirname "$s")/*.h"]=1
done
# A folder without headers leaves its *.h pattern unmatched, which tar reports as an error;
# what matters is that every source came out, checked below.
tar -xJf "$tarball" -C "$work" --strip-components=1 --wildcards --no-wildcards-match-slash \
  "${!patterns[@]}" 2>"$work/tar.log" || true
for s in "${sources[@]}"; do
  [[ -r $work/$s ]] || { cat "$work/tar.log"; echo "FAIL: $s is not in $tarball"; exit 1; }
done
for p in "${patches[@]}"; do
  patch -d "$work" -p1 --quiet --forward <"$p" || { echo "FAIL: $p does not apply"; exit 1; }
done
objs=()
for s in "${sources[@]}"; do objs+=("${s%.c}.o"); done
# A composite module: its name is free of every member's, so MODULE.ko can link a member that
# is itself called MODULE.c.
cat >"$work/Kbuild" <<EOF
obj-m := $module.o
$module-y := ${objs[*]}
EOF
log=$out/$module.log
if ! nice make -C "$headers" M="$work" -j2 modules >"$log" 2>&1; then
  tail -30 "$log"
  echo "FAIL: building $module.ko against $headers failed (full log: $log)"
  exit 1
fi
cp "$work/$module.ko" "$ko"
echo "$key" >"$stamp"
echo "built: $ko in $(($(date +%s) - start)) s (kernel $kver, $image_version)"
echo "$ko"
