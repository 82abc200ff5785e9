#!/usr/bin/env bash
# The tethered display against virtio-gpu in a VM (issue #7; docs/display.md "The VM test"):
# boots Debian's kernel under TCG with a virtio-gpu-pci device (no virgl: 2D only), loads
# virtio-gpu, and runs the KMS gtest binary there. Exit 77 (ctest: skipped) with the reason
# when the VM cannot run here.
# Usage: check_kms.sh TEST_BINARY [GTEST_ARGS...]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
binary=$(realpath "$1")
shift
[[ -x $binary ]] || { echo "FAIL: $binary is not built"; exit 1; }
# Mesa in the guest is the host's, and virtio-gpu without virgl has no 3D, so GBM and EGL
# run on kms_swrast: llvmpipe drawing into dumb buffers that the CRTC scans out. Mesa 22.3's
# loader picks kms_swrast_dri.so by itself here (EGL_LOG_LEVEL=debug shows that one dlopen);
# MESA_LOADER_DRIVER_OVERRIDE pins it so another Mesa cannot change the path under test.
# No udev in the guest: the module is loaded by hand, then devtmpfs has /dev/dri/card0.
exec nice "$here/run_in_vm.sh" -t "${PROBELESS_VM_TIMEOUT:-420}" -d virtio-gpu-pci -- \
  env PROBELESS_REQUIRE_KMS=1 MESA_LOADER_DRIVER_OVERRIDE=kms_swrast \
  MESA_SHADER_CACHE_DISABLE=true sh -c \
  'modprobe virtio-gpu && exec "$0" --gtest_color=no "$@"' \
  "$binary" "$@"
