#!/usr/bin/env bash
# The libcamera fisheye source against vimc in a VM (issue #7; docs/drivers.md "libcamera
# fisheye"): builds vimc.ko out of tree (build_module.sh; Debian's config leaves
# CONFIG_VIDEO_VIMC off), boots Debian's kernel under TCG, starts systemd-udevd (libcamera
# enumerates cameras and hears of their removal through udev), loads vimc with its
# dependencies and runs the libcamera gtest binary there. Exit 77 (ctest: skipped) with the
# reason when the module cannot be built or the VM cannot run here.
# Usage: check_vimc.sh CACHE_DIR TEST_BINARY [GTEST_ARGS...]
#        check_vimc.sh --in-guest MODULE.ko TEST_BINARY [GTEST_ARGS...]   (inside the VM)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)

if [[ ${1:-} == --in-guest ]]; then
  ko=$2 binary=$3
  shift 3
  # udevadm refuses to act in a chroot, which the guest's root is (run_in_vm.sh).
  export SYSTEMD_IGNORE_CHROOT=1
  # vimc's dependencies (videodev, mc, videobuf2-*, v4l2-tpg) from the module's .modinfo,
  # each through modprobe and the host's modules.dep.
  for dep in $(modinfo -F depends "$ko" | tr ',' ' '); do modprobe "$dep"; done
  # udevd before vimc: it records the media and video nodes as they appear (libcamera waits
  # for a media device's nodes in udev's database); /run is a tmpfs in the guest.
  /lib/systemd/systemd-udevd --daemon
  insmod "$ko"
  udevadm trigger --action=add
  udevadm settle -t 30
  echo "VM: vimc $(ls /dev/media* | tr '\n' ' ')"
  export PROBELESS_REQUIRE_VIMC=1
  exec "$binary" --gtest_color=no "$@"
fi

(($# >= 2)) || { echo "usage: $0 CACHE_DIR TEST_BINARY [GTEST_ARGS...]" >&2; exit 2; }
cache=$1
binary=$(realpath "$2")
shift 2
[[ -x $binary ]] || { echo "FAIL: $binary is not built"; exit 1; }
# What run_in_vm.sh would skip on anyway, before a minute of module build.
[[ $(id -u) == 0 ]] || { echo "SKIP: needs root (the VM chroots into the host's files)"; exit 77; }
command -v qemu-system-x86_64 >/dev/null ||
  { echo "SKIP: qemu-system-x86_64 is not installed (scripts/setup.sh)"; exit 77; }
[[ -x /lib/systemd/systemd-udevd ]] || { echo "SKIP: no systemd-udevd for the guest"; exit 77; }
[[ -r /usr/lib/x86_64-linux-gnu/libcamera/ipa_vimc.so ]] ||
  { echo "SKIP: no vimc IPA module (libcamera-ipa, scripts/setup.sh)"; exit 77; }
v=drivers/media/test-drivers/vimc
set +e
built=$("$here/build_module.sh" "$cache" vimc $v/vimc-core.c $v/vimc-common.c \
  $v/vimc-streamer.c $v/vimc-capture.c $v/vimc-debayer.c $v/vimc-scaler.c $v/vimc-sensor.c \
  $v/vimc-lens.c)
status=$?
set -e
echo "$built"
((status == 0)) || exit $status
ko=$(tail -1 <<<"$built")
exec nice "$here/run_in_vm.sh" -t "${PROBELESS_VM_TIMEOUT:-420}" -- \
  "$here/check_vimc.sh" --in-guest "$ko" "$binary" "$@"
