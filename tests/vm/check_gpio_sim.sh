#!/usr/bin/env bash
# The GPIO trigger and strobe against gpio-sim in a VM (issue #7; docs/gpio.md): builds
# gpio-sim.ko out of tree (build_module.sh; Debian's config leaves CONFIG_GPIO_SIM off), boots
# Debian's kernel under TCG, loads the module with its dependencies, makes a simulated chip
# through configfs and runs the gpio-sim gtest binary there. Exit 77 (ctest: skipped) with the
# reason when the module cannot be built or the VM cannot run here.
# Usage: check_gpio_sim.sh CACHE_DIR TEST_BINARY [GTEST_ARGS...]
#        check_gpio_sim.sh --in-guest MODULE.ko TEST_BINARY [GTEST_ARGS...]   (inside the VM)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# The chip the test looks up by label, and its lines: 0 trigger (output), 1 strobe (input),
# 2 and 3 spare for the error cases.
label=probeless-gpio-sim
lines=4

if [[ ${1:-} == --in-guest ]]; then
  ko=$2 binary=$3
  shift 3
  # gpio-sim's dependencies from the module itself (modinfo reads its .modinfo; today only
  # configfs, which Debian builds as a module), each through modprobe and the host's
  # modules.dep, so their own dependencies come first.
  for dep in $(modinfo -F depends "$ko" | tr ',' ' '); do modprobe "$dep"; done
  insmod "$ko"
  config=/sys/kernel/config
  grep -q " $config configfs" /proc/mounts || mount -t configfs none "$config"
  chip=$config/gpio-sim/probeless
  mkdir "$chip" "$chip/bank0"
  echo "$label" >"$chip/bank0/label"
  echo "$lines" >"$chip/bank0/num_lines"
  mkdir "$chip/bank0/line0" "$chip/bank0/line1"
  echo trigger >"$chip/bank0/line0/name"
  echo strobe >"$chip/bank0/line1/name"
  echo 1 >"$chip/live"
  echo "VM: gpio-sim $(cat "$chip/dev_name")/$(cat "$chip/bank0/chip_name") '$label', $lines lines"
  export PROBELESS_REQUIRE_GPIO_SIM=1 PROBELESS_GPIO_SIM_LABEL=$label
  exec "$binary" --gtest_color=no "$@"
fi

(($# >= 2)) || { echo "usage: $0 CACHE_DIR TEST_BINARY [GTEST_ARGS...]" >&2; exit 2; }
cache=$1
binary=$(realpath "$2")
shift 2
[[ -x $binary ]] || { echo "FAIL: $binary is not built"; exit 1; }
# What run_in_vm.sh would skip on anyway, before half a minute of module build.
[[ $(id -u) == 0 ]] || { echo "SKIP: needs root (the VM chroots into the host's files)"; exit 77; }
command -v qemu-system-x86_64 >/dev/null ||
  { echo "SKIP: qemu-system-x86_64 is not installed (scripts/setup.sh)"; exit 77; }
# irq_sim.c travels inside gpio-sim.ko: Debian's kernel has no CONFIG_IRQ_SIM either.
set +e
built=$("$here/build_module.sh" -p "$here/patches/irq_sim-export.patch" "$cache" gpio-sim \
  drivers/gpio/gpio-sim.c kernel/irq/irq_sim.c)
status=$?
set -e
echo "$built"
((status == 0)) || exit $status
ko=$(tail -1 <<<"$built")
exec nice "$here/run_in_vm.sh" -t "${PROBELESS_VM_TIMEOUT:-420}" -- \
  "$here/check_gpio_sim.sh" --in-guest "$ko" "$binary" "$@"
