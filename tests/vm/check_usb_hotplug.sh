#!/usr/bin/env bash
# The libusb hotplug watcher against real USB hotplug (issue #7; docs/drivers.md "USB
# hotplug and reset"): the VM of run_in_vm.sh gets an emulated xHCI controller and a QEMU
# monitor on a local TCP port; the guest loads xhci_pci, starts systemd-udevd (Debian's
# libusb learns of hotplug through udev) and runs the watcher for QEMU's vendor 0627; this
# script hot-adds a usb-kbd through the monitor when the guest is ready, and removes it
# once the guest saw it arrive. Exit 77 (skipped) with the reason when the VM cannot run.
# Usage: check_usb_hotplug.sh WATCHER_BINARY
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
binary=$(realpath "$1")
[[ -x $binary ]] || { echo "FAIL: $binary is not built"; exit 1; }
[[ -x /lib/systemd/systemd-udevd ]] || { echo "SKIP: no systemd-udevd for the guest"; exit 77; }

port=$((20000 + RANDOM % 20000))
log=$(mktemp /tmp/probeless-usb-vm.XXXXXX)
trap 'rm -f "$log"; [[ -n ${vm:-} ]] && kill "$vm" 2>/dev/null || true' EXIT
PROBELESS_VM_QEMU_ARGS="-device qemu-xhci,id=xhci -monitor tcp:127.0.0.1:$port,server=on,wait=off" \
  nice "$here/run_in_vm.sh" -t "${PROBELESS_VM_TIMEOUT:-400}" -- sh -c \
  'modprobe xhci_pci && /lib/systemd/systemd-udevd --daemon && exec "$0"' "$binary" \
  >"$log" 2>&1 &
vm=$!

# Waits for a line in the guest's console; fails when the VM ends first.
await() {
  local deadline=$((SECONDS + $2)) status
  until grep -q "$1" "$log"; do
    if ! kill -0 "$vm" 2>/dev/null; then
      wait "$vm" && status=0 || status=$?
      vm=
      cat "$log"
      ((status == 77)) && exit 77
      echo "FAIL: the VM ended (status $status) before the guest said '$1'"
      exit 1
    fi
    if ((SECONDS > deadline)); then
      cat "$log"
      echo "FAIL: no '$1' from the guest within $2 s"
      exit 1
    fi
    sleep 0.5
  done
}
monitor() {
  exec 3<>"/dev/tcp/127.0.0.1/$port"
  printf '%s\n' "$1" >&3
  sleep 1
  exec 3<&- 3>&-
}

await PROBELESS_USB_READY 360
monitor "device_add usb-kbd,id=probelesskbd,bus=xhci.0"
await PROBELESS_USB_ARRIVED 120
monitor "device_del probelesskbd"
wait "$vm" && status=0 || status=$?
vm=
cat "$log"
exit "$status"
