#!/usr/bin/env bash
# Runs a command inside a QEMU VM booted from Debian's own kernel (linux-image-amd64), so
# driver tests meet real kernel drivers (vivid, ...) rather than fakes (issue #7,
# docs/drivers.md "The VM harness"). No disk image: a busybox-static initramfs built here
# loads the virtio/9p modules, mounts the host's / read-only over 9p, and chroots into it, so
# the command and its shared libraries are the host's own files. The command's exit status
# comes back as a marker line on the serial console.
#
# Usage: run_in_vm.sh [-t TIMEOUT_S] [-m MEM] [-w DIR] [-d DEVICE]... -- COMMAND [ARGS...]
#   -w DIR     working directory of the command inside the guest (default: the current one)
#   -d DEVICE  an extra QEMU device (`-device DEVICE`), e.g. virtio-gpu-pci; repeatable. Its
#              driver is the command's to load (modprobe finds the host's modules).
#   -s         boot the host's systemd as PID 1 (switch_root into the 9p root, /etc and /var
#              writable copies in tmpfs) and run the command as a oneshot unit after
#              basic.target, for tests of the systemd units (check_systemd_unit.sh)
# Exits with the command's status, 77 when the VM cannot run here (the reason on stdout),
# 124 when the VM timed out. PROBELESS_VM_KERNEL picks another /boot/vmlinuz-*.
# PROBELESS_VM_QEMU_ARGS adds QEMU arguments (split on spaces), e.g. an emulated USB
# controller and a monitor for hot-adding devices (check_usb_hotplug.sh).
set -euo pipefail

timeout_s=300 mem=768M workdir=$PWD devices=() boot_systemd=0
while getopts "t:m:w:d:s" opt; do
  case $opt in
    t) timeout_s=$OPTARG ;; m) mem=$OPTARG ;; w) workdir=$OPTARG ;; d) devices+=(-device "$OPTARG") ;;
    s) boot_systemd=1 ;;
    *) echo "usage: $0 [-t S] [-m MEM] [-w DIR] [-d DEVICE]... -- COMMAND..." >&2; exit 2 ;;
  esac
done
shift $((OPTIND - 1))
[[ ${1:-} == -- ]] && shift
(($# > 0)) || { echo "usage: $0 [-t S] [-m MEM] [-w DIR] [-d DEVICE]... -- COMMAND..." >&2; exit 2; }

skip() { echo "SKIP: $*"; exit 77; }
qemu=$(command -v qemu-system-x86_64) || skip "qemu-system-x86_64 is not installed (scripts/setup.sh)"
busybox=/bin/busybox
[[ -x $busybox ]] && file -L "$busybox" 2>/dev/null | grep -q static ||
  busybox=$(command -v busybox.static 2>/dev/null || true)
[[ -n $busybox && -x $busybox ]] || skip "busybox-static is not installed (scripts/setup.sh)"
kernel=${PROBELESS_VM_KERNEL:-$(ls -1 /boot/vmlinuz-* 2>/dev/null | sort -V | tail -1)}
[[ -n $kernel && -r $kernel ]] || skip "no readable /boot/vmlinuz-* (linux-image-amd64)"
kver=${kernel#/boot/vmlinuz-}
moddir=/lib/modules/$kver
[[ -r $moddir/modules.dep ]] || skip "no $moddir/modules.dep for kernel $kver"
[[ $(id -u) == 0 ]] || skip "needs root (the guest chroots into the host's files as root)"

scratch=$(mktemp -d /tmp/v4l2-vm.XXXXXX)
trap 'rm -rf "$scratch"' EXIT
root=$scratch/initramfs
mkdir -p "$root"/{bin,dev,proc,sys,host,lib/modules}
cp "$busybox" "$root/bin/busybox"

# The modules that reach the 9p root, in load order: each one's dependencies (modules.dep
# lists them all, deepest last) before it. Everything else is loaded from the host's
# /lib/modules once the guest is inside the chroot.
declare -A seen=()
order=()
add_module() {
  local line deps path
  line=$(grep -E "/$1\.ko(\.[a-z]+)?:" "$moddir/modules.dep" | head -1) ||
    skip "module $1 is not in $moddir/modules.dep"
  path=${line%%:*}
  read -ra deps <<<"${line#*:}"
  for ((i = ${#deps[@]} - 1; i >= 0; i--)); do
    [[ -n ${seen[${deps[i]}]:-} ]] || { seen[${deps[i]}]=1; order+=("${deps[i]}"); }
  done
  [[ -n ${seen[$path]:-} ]] || { seen[$path]=1; order+=("$path"); }
}
for m in virtio_pci 9pnet_virtio 9p; do add_module "$m"; done
for path in "${order[@]}"; do
  case $path in
    *.ko) cp "$moddir/$path" "$root/lib/modules/" ;;
    *.ko.xz) xz -dc "$moddir/$path" >"$root/lib/modules/$(basename "${path%.xz}")" ;;
    *) skip "cannot unpack module $path" ;;
  esac
  echo "$(basename "${path%.xz}")" >>"$root/modules"
done

# The sanitizer runtime's options travel with the command (ctest --preset asan sets them on
# the host; the guest's init starts from an empty environment).
sanitizer_env=()
for var in ASAN_OPTIONS LSAN_OPTIONS UBSAN_OPTIONS; do
  [[ -n ${!var:-} ]] && sanitizer_env+=("$var=${!var}")
done
((${#sanitizer_env[@]} > 0)) && set -- env "${sanitizer_env[@]}" "$@"
printf '%q ' "$@" >"$root/command"
printf '%s' "$workdir" >"$root/workdir"
append=${PROBELESS_VM_APPEND:-quiet loglevel=3}
if ((boot_systemd)); then
  [[ -x /lib/systemd/systemd ]] || skip "no /lib/systemd/systemd to boot"
  touch "$root/boot_systemd"
fi
# The guest's /tmp is a fresh tmpfs (the host's is read-only over 9p). A checkout or build under
# the host's /tmp (the working directory, this script's tree, a path in the command) is
# bound back into it: one line per top-level entry of /tmp to keep.
keep_tmp() {
  local p
  p=$(realpath -m -- "$1")
  if [[ $p == /tmp/?* ]]; then
    p=${p#/tmp/}
    printf '%s\n' "${p%%/*}"
  fi
}
{
  keep_tmp "$workdir"
  keep_tmp "$(dirname "${BASH_SOURCE[0]}")"
  for arg in "$@"; do if [[ $arg == /* ]]; then keep_tmp "$arg"; fi; done
} | sort -u >"$root/keep_tmp"
cat >"$root/init" <<'EOF'
#!/bin/busybox sh
/bin/busybox --install -s /bin
mount -t proc proc /proc
mount -t sysfs sys /sys
mount -t devtmpfs dev /dev
for m in $(cat /modules); do insmod /lib/modules/$m || echo "VM: insmod $m failed"; done
if ! mount -t 9p -o trans=virtio,version=9p2000.L,ro,msize=512000,cache=loose host /host; then
  echo "PROBELESS_VM_EXIT=setup"; poweroff -f
fi
mount -t proc proc /host/proc
mount -t sysfs sys /host/sys
mount -t devtmpfs dev /host/dev
mkdir /hosttmp
mount -o bind /host/tmp /hosttmp
mount -t tmpfs tmp /host/tmp
while IFS= read -r d; do
  if [ -d "/hosttmp/$d" ]; then mkdir -p "/host/tmp/$d"; else touch "/host/tmp/$d"; fi
  mount -o bind "/hosttmp/$d" "/host/tmp/$d" || echo "VM: cannot bind /tmp/$d"
done </keep_tmp
mount -t tmpfs run /host/run
cmd=$(cat /command)
if [ -f /boot_systemd ]; then
  # systemd wants a writable /etc (machine-id, the units the test installs) and /var.
  mkdir /etc.rw
  mount -t tmpfs etc /etc.rw
  cp -a /host/etc/. /etc.rw/
  mount --move /etc.rw /host/etc
  mount -t tmpfs var /host/var
  mkdir -p /host/var/lib /host/var/cache /host/var/log /host/var/tmp /host/etc/probeless-vm
  printf '#!/bin/sh\ncd %s && %s\necho "PROBELESS_VM_EXIT=$?" >/dev/ttyS0\nsystemctl --force --force poweroff\n' \
    "'$(cat /workdir)'" "$cmd" >/host/etc/probeless-vm/command.sh
  chmod +x /host/etc/probeless-vm/command.sh
  printf '[Unit]\nDescription=the VM harness command\n[Service]\nType=oneshot\nExecStart=/etc/probeless-vm/command.sh\nStandardOutput=tty\nStandardError=tty\nTTYPath=/dev/ttyS0\n' \
    >/host/etc/systemd/system/probeless-vm-command.service
  umount /host/proc /host/sys /host/dev
  # The unit on systemd's own command line: it ignored systemd.unit= on the kernel's here.
  exec switch_root /host /lib/systemd/systemd --unit=probeless-vm-command.service \
    --show-status=0
fi
chroot /host /bin/sh -c "cd '$(cat /workdir)' && exec $cmd"
echo "PROBELESS_VM_EXIT=$?"
poweroff -f
EOF
chmod +x "$root/init"
(cd "$root" && find . | cpio -o -H newc --quiet | gzip -1) >"$scratch/initramfs.cpio.gz"

log=$scratch/console.log
start=$(date +%s)
set +e
# TCG on purpose: CI machines have no /dev/kvm, and the test must mean the same everywhere.
# Two vCPUs as the host has; a quiet console keeps the boot to a few seconds.
timeout --foreground "$timeout_s" "$qemu" -accel tcg -cpu max -smp 2 -m "$mem" -nodefaults \
  -display none -no-reboot -serial stdio -monitor none \
  -kernel "$kernel" -initrd "$scratch/initramfs.cpio.gz" \
  -append "console=ttyS0 $append panic=-1 rdinit=/init" \
  -virtfs local,path=/,mount_tag=host,security_model=none,readonly=on,multidevs=remap \
  "${devices[@]}" ${PROBELESS_VM_QEMU_ARGS:-} </dev/null | tee "$log"
qemu_status=${PIPESTATUS[0]}
set -e
echo "VM: $(($(date +%s) - start)) s (kernel $kver, TCG)"
((qemu_status == 124)) && { echo "FAIL: the VM did not finish within ${timeout_s} s"; exit 124; }
status=$(sed -n 's/.*PROBELESS_VM_EXIT=\([0-9a-z]*\).*/\1/p' "$log" | tail -1 | tr -d '\r')
[[ -n $status ]] || { echo "FAIL: the VM stopped without reporting (qemu status $qemu_status)"; exit 1; }
[[ $status == setup ]] && { echo "FAIL: the guest could not mount the host over 9p"; exit 1; }
exit "$status"
