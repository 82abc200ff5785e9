#!/usr/bin/env bash
# The V4L2 source against vivid in a VM (issue #7; docs/drivers.md "The VM harness"): boots
# Debian's kernel under TCG, loads vivid with one capture node, and runs the vivid gtest
# binary there. Exit 77 (ctest: skipped) with the reason when the VM cannot run here.
# Usage: check_vivid.sh TEST_BINARY [GTEST_ARGS...]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
binary=$(realpath "$1")
shift
[[ -x $binary ]] || { echo "FAIL: $binary is not built"; exit 1; }
# n_devs=1 node_types=0x1: one vivid instance with a video capture node and nothing else
# (no output, VBI, radio, SDR or touch nodes to probe under TCG).
exec nice "$here/run_in_vm.sh" -t "${PROBELESS_VM_TIMEOUT:-420}" -- \
  env PROBELESS_REQUIRE_VIVID=1 sh -c \
  'modprobe vivid n_devs=1 node_types=0x1 && exec "$0" --gtest_color=no "$@"' \
  "$binary" "$@"
