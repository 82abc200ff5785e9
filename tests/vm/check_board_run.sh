#!/usr/bin/env bash
# `probeless run --board NAME` with the shipped /etc/probeless/probeless.toml (systemd/) on
# real drivers in a VM (issue #18): vivid is the fisheye (V4L2, by its card name), OpenNI2's
# Dummy device the RGB-D sensor, both named by a board file this test writes (board `vmrig`,
# found by name under $PROBELESS_BOARD_DIR) with a calibration file of the frames' sizes.
# /status over loopback must show that board's two devices, frames from both and through the
# pipeline, and no "sim" anywhere. Then the errors: the calibration file missing (named),
# and one of another colour size (both sizes named).
# PoCL's kernel cache is filled on the host first (POCL_KERNELLIB_NAME=avx2: the kernel
# library and LLVM CPU, "haswell", that PoCL picks in the TCG guest, so the guest hits the
# cache; a cold compile under TCG took over 4 minutes on a loaded host), with the PRT bake of
# the shipped scene (107 s under TCG) and Mesa's shader cache. The test board turns the light
# stage off to keep the guest's two emulated cores for what is under test: the first run
# with it on had no frame out within 6 minutes (2026-11-26), most of it the then uncached
# bake; light on was not measured again. The fisheye still streams (frames.fisheye_in).
# Usage: check_board_run.sh SOURCE_DIR PROBELESS_BINARY CACHE_DIR
#        check_board_run.sh --in-guest SOURCE_DIR PROBELESS_BINARY POCL_CACHE   (in the VM)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)

if [[ ${1:-} == --in-guest ]]; then
  src=$2 binary=$3 warm=$4
  passed=0 failed=0
  check() {  # check DESCRIPTION COMMAND...
    local what=$1; shift
    if "$@" >/dev/null; then passed=$((passed + 1)); echo "ok: $what"
    else failed=$((failed + 1)); echo "FAIL: $what"; fi
  }
  say() { echo "VM: [$(date +%T)] $*"; }
  ip link set lo up
  modprobe vivid n_devs=1 node_types=0x1
  say "vivid: $(cat /sys/class/video4linux/video0/name)"
  work=/tmp/board-run
  mkdir -p "$work/boards/vmrig"
  cp -r "$warm" "$work/pocl"
  # XDG_CACHE_HOME: the host-made Mesa shader cache and the scene's PRT bake (107 s under TCG).
  export POCL_CACHE_DIR=$work/pocl XDG_CACHE_HOME=$work/pocl/xdg PROBELESS_BOARD_DIR=$work/boards
  calibration() {  # calibration FILE COLOUR_W COLOUR_H
    cat >"$1" <<CAL
[rgb]
width = $2
height = $3
fx = $(($2 * 525 / 640)).0
fy = $(($2 * 525 / 640)).0
cx = $(($2 / 2)).0
cy = $(($3 / 2)).0
[fisheye]
model = "kannala_brandt"
width = 320
height = 180
fx = 60.0
fy = 60.0
cx = 160.0
cy = 90.0
k = [0.0, 0.0, 0.0, 0.0]
max_theta = 1.5
[extrinsics]
T_rig_rgb = {translation = [0.0, 0.0, 0.0], rotation_xyzw = [0.0, 0.0, 0.0, 1.0]}
T_rig_fisheye = {translation = [0.0, -0.05, 0.02], rotation_xyzw = [-0.7071067811865476, 0.0, 0.0, 0.7071067811865476]}
depth_baseline_m = 0.075
CAL
  }
  board() {  # board CALIBRATION_FILE
    cat >"$work/boards/vmrig/board.toml" <<BOARD
[about]
name = "vmrig"
summary = "the VM's rig: OpenNI2 Dummy RGB-D, vivid fisheye (tests/vm/check_board_run.sh)"
[source]
rig = "openni2:Dummy?size=320x240&hotplug=0+v4l2:vivid?size=320x180&fps=30&latency=0&calibration=$1"
[opencl]
platform = "Portable Computing Language"
[bracket]
gpio_chip = ""
[http]
address = "127.0.0.1"
port = 8080
[display]
enabled = false
[rtsp]
enabled = false
[light]
enabled = false
BOARD
  }
  # exec: a backgrounded function is a subshell, and SIGTERM must reach probeless itself.
  run_board() { exec "$binary" run --board vmrig --config "$src/systemd/probeless.toml" "$@"; }

  # 1. The board's devices, frames through the pipeline, no sim.
  calibration "$work/calibration.toml" 320 240
  board "$work/calibration.toml"
  start=$(date +%s)
  run_board >"$work/run.log" 2>&1 &
  pid=$!
  status='{}'
  say "probeless run --board vmrig started"
  for i in $(seq 1 240); do
    status=$(curl -sf --max-time 5 http://127.0.0.1:8080/status || echo '{}')
    # Frames processed with the RGB-D source streaming, not only NO SIGNAL frames out: the
    # Dummy device can stall at start under TCG beside a loaded host and is then reopened.
    # And out: the output thread counts a frame after processing does, so right when the
    # third is processed the second may be the last out (a CI run saw processed 3, out 2).
    jq -e '.frames.processed >= 3 and .frames.out >= 3 and .frames.fisheye_in >= 3 and
      .sources.rgbd.state == "streaming"' <<<"$status" >/dev/null && break
    kill -0 $pid 2>/dev/null || break
    ((i % 15)) || say "$(jq -c '{state, frames}' <<<"$status") $(tail -1 "$work/run.log")"
    sleep 2
  done
  echo "VM: /status after $(($(date +%s) - start)) s: $(jq -c '{state, frames, sources}' <<<"$status")"
  check "frames out of the pipeline" jq -e '.frames.out >= 3' <<<"$status"
  check "RGB-D frames from the Dummy device" jq -e '.frames.rgbd_in >= 3' <<<"$status"
  check "fisheye frames from vivid" jq -e '.frames.fisheye_in >= 3' <<<"$status"
  check "the RGB-D source is OpenNI2's Dummy device" \
    jq -e '.sources.rgbd.name == "openni2:Dummy" and .sources.rgbd.state == "streaming"' <<<"$status"
  check "the fisheye is vivid over V4L2" \
    jq -e '.sources.fisheye.name | test("^v4l2:.*vivid|^v4l2:/dev/video")' <<<"$status"
  check "nothing in /status says sim" \
    jq -e '[.. | strings | select(test("^sim($|:| )"))] | length == 0' <<<"$status"
  # || true: a service that already died (a crash) must still reach the checks and the log.
  kill -TERM $pid 2>/dev/null || true
  wait $pid && code=0 || code=$?
  check "SIGTERM stops it cleanly (exit $code)" test "$code" = 0
  if ((failed > 0)); then cat "$work/run.log"; fi
  # The source's recoveries (stalls, reopens) beside a loaded host, for the log.
  grep -E "stall|reopen" "$work/run.log" | sed 's/^/VM: run.log: /' | head -5 || true

  # 2. The board's calibration file missing: named, before anything streams.
  board "$work/no-such-calibration.toml"
  out=$(run_board 2>&1) && code=0 || code=$?
  echo "VM: missing calibration: exit $code: $(grep -m1 -i 'error' <<<"$out")"
  check "a missing calibration file stops the start" test "$code" != 0
  check "... and is named" grep -q "$work/no-such-calibration.toml" <<<"$out"

  # 3. A calibration of another colour size: both sizes named.
  calibration "$work/calibration-640.toml" 640 480
  board "$work/calibration-640.toml"
  out=$(timeout 200 "$binary" run --board vmrig --config "$src/systemd/probeless.toml" 2>&1) &&
    code=0 || code=$?
  echo "VM: 640x480 calibration: exit $code: $(grep -m1 'calibration' <<<"$out")"
  grep -q "calibration's colour camera" <<<"$out" || echo "$out" | tail -20
  check "a calibration of another size stops the service" test "$code" = 1
  check "... naming both sizes" grep -q "320 x 240, but the calibration's colour camera is 640 x 480" <<<"$out"
  echo "board run: $passed passed, $failed failed"
  ((failed == 0))
  exit
fi

(($# == 3)) || { echo "usage: $0 SOURCE_DIR PROBELESS_BINARY CACHE_DIR" >&2; exit 2; }
src=$(realpath "$1") binary=$(realpath "$2") cache=$3
[[ -x $binary ]] || { echo "FAIL: $binary is not built"; exit 1; }
for tool in curl jq ip; do
  command -v $tool >/dev/null || { echo "SKIP: no $tool for the guest"; exit 77; }
done
"$here/warm_pocl_cache.sh" "$binary" "$cache/pocl-avx2" || exit $?
exec nice "$here/run_in_vm.sh" -t "${PROBELESS_VM_TIMEOUT:-420}" -- \
  "$here/check_board_run.sh" --in-guest "$src" "$binary" "$(realpath "$cache/pocl-avx2")"
