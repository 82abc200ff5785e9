#!/usr/bin/env bash
# The appliance apart from the lab (issue #16, docs/architecture.md "The lab"): of OpenCV the
# service binary links exactly what world anchoring with a marker needs (issue #17,
# docs/appliance.md "OpenCV in the appliance"): core, imgproc, calib3d and aruco directly, and
# nothing but calib3d's own features2d and flann through them; the rest of OpenCV (ximgproc,
# imgcodecs, highgui, videoio, rgbd, ...) is the lab's. `probeless eval` / `probeless bench`
# still reach the lab binary beside it.
# Usage: check_appliance_deps.sh PROBELESS_BINARY
set -u
bin=$1
lab=$(dirname "$bin")/probeless-lab
fail=0
opencv_modules() { grep -o 'libopencv_[a-z0-9_]*' | sed 's/^libopencv_//' | sort -u | tr '\n' ' '; }
direct=$(readelf -d "$bin" | grep NEEDED | opencv_modules)
[ "$direct" = "aruco calib3d core imgproc " ] ||
  { echo "FAIL: $bin links OpenCV modules [$direct], expected [aruco calib3d core imgproc ]"; fail=1; }
closure=$(ldd "$bin" | opencv_modules)
for m in $closure; do
  case $m in aruco|calib3d|core|imgproc|features2d|flann) ;;
    *) echo "FAIL: $bin loads libopencv_$m (only core, imgproc, calib3d, aruco and calib3d's"\
            "features2d and flann are allowed)"; fail=1 ;;
  esac
done
ldd "$lab" | grep -qi opencv || { echo "FAIL: $lab does not link OpenCV: is it the lab?"; fail=1; }
# The hand-on: same flags, same exit codes as before the split.
"$bin" eval --help | grep -q occlusion || { echo "FAIL: probeless eval --help"; fail=1; }
"$bin" --log-level warn bench --help | grep -q pipeline || { echo "FAIL: probeless bench --help"; fail=1; }
"$bin" eval no-such-evaluation >/dev/null 2>&1; rc=$?
[ $rc -ne 0 ] || { echo "FAIL: an unknown evaluation exited 0"; fail=1; }
"$bin" --help | grep -q eval || { echo "FAIL: probeless --help does not list eval"; fail=1; }
# Without the lab installed, a clear message and exit 1 (a copy of the binary alone).
tmp=$(mktemp -d) && trap 'rm -rf "$tmp"' EXIT
cp "$bin" "$tmp/probeless"
out=$("$tmp/probeless" eval occlusion 2>&1); rc=$?
[ $rc -eq 1 ] && grep -q "probeless-lab" <<<"$out" ||
  { echo "$out"; echo "FAIL: without the lab: exit $rc, no message naming probeless-lab"; fail=1; }
[ $fail -eq 0 ] && echo "appliance: OpenCV [$direct] only; eval and bench reach the lab: ok"
exit $fail
