#!/usr/bin/env bash
# The appliance's unit under a real systemd (issue #20 item 7): boots Debian's kernel under TCG
# with the host's systemd as PID 1 (run_in_vm.sh -s), installs systemd/ as the .deb would
# (sysusers, tmpfiles, the unit and the socket; ExecStart pointed at the build's binary, the
# shipped config with the RGB-D source set to OpenNI2's Dummy device: the sim's scene bake
# alone would take minutes under TCG), then checks:
#   1. `systemctl start probeless` returns with the unit active: READY=1 reached with the
#      whole sandbox on (ProtectSystem=strict, seccomp, no new privileges, the limits);
#   2. socket activation: with the service stopped and probeless.socket listening, a request
#      to the socket starts the service, which answers /status on the socket systemd passed;
#   3. an [output] dir outside the state directory stops the start with the reason in the
#      journal, and one under /var/lib/probeless is written to.
# PoCL's kernel cache is warmed on the host (warm_pocl_cache.sh) and put in the unit's
# CacheDirectory. Usage: check_systemd_unit.sh SOURCE_DIR PROBELESS_BINARY CACHE_DIR
#        check_systemd_unit.sh --in-guest SOURCE_DIR PROBELESS_BINARY POCL_CACHE   (in the VM)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)

if [[ ${1:-} == --in-guest ]]; then
  src=$2/systemd binary=$3 warm=$4
  passed=0 failed=0
  check() {  # check DESCRIPTION COMMAND...
    local what=$1; shift
    if "$@"; then passed=$((passed + 1)); echo "ok: $what"
    else failed=$((failed + 1)); echo "FAIL: $what"; fi
  }
  ip link set lo up
  # As the package's maintainer scripts do (debian/: dh_installsysusers, dh_installtmpfiles).
  systemd-sysusers "$src/probeless.sysusers"
  systemd-tmpfiles --create "$src/probeless.tmpfiles"
  sed "s|^ExecStart=/usr/bin/probeless|ExecStart=$binary|" "$src/probeless.service" \
    >/etc/systemd/system/probeless.service
  cp "$src/probeless.socket" /etc/systemd/system/
  # Start-up under TCG beside a loaded host took 56 s in one suite run and more than the
  # default 90 s TimeoutStartSec in the next (2026-11-27; a board starts in seconds): give the
  # emulated start 5 minutes, so the test checks the unit, not the emulator's speed.
  mkdir -p /etc/systemd/system/probeless.service.d
  printf '[Service]\nTimeoutStartSec=300\n' >/etc/systemd/system/probeless.service.d/tcg.conf
  # A checkout under /tmp: the unit's PrivateTmp=yes hides the build's binary and the source
  # tree from the service (203/EXEC, all checks failed from a clone in /tmp). Bind them back
  # read-only, which systemd applies over the private /tmp; the shipped unit is unchanged.
  for path in "$(dirname "$binary")" "$(dirname "$src")"; do
    if [[ $path == /tmp/* ]]; then
      mkdir -p /etc/systemd/system/probeless.service.d
      printf '[Service]\nBindReadOnlyPaths=%s\n' "$path" \
        >>/etc/systemd/system/probeless.service.d/checkout-under-tmp.conf
    fi
  done
  config() {  # config [EXTRA TOML...]
    { cat "$src/probeless.toml"
      printf '[source]\nrig = "openni2:Dummy?size=320x240&hotplug=0"\n'
      for extra in "$@"; do printf '%s\n' "$extra"; done
    } >/etc/probeless/probeless.toml
  }
  config
  # The unit's CacheDirectory: PoCL's kernels and the scene's PRT bake, made on the host.
  mkdir -p /var/cache/probeless
  cp -r "$warm" /var/cache/probeless/pocl
  cp -r "$warm/xdg/probeless/prt" /var/cache/probeless/prt
  systemctl daemon-reload

  # 1. READY with the sandbox on.
  start=$(date +%s.%N)
  systemctl start probeless.service && code=0 || code=$?
  ready_s=$(echo "$(date +%s.%N) - $start" | bc)
  echo "VM: systemctl start probeless: exit $code after ${ready_s} s"
  check "the unit reached READY (systemctl start returned 0)" test "$code" = 0
  check "it is active/running" test "$(systemctl show -P SubState probeless)" = running
  pid=$(systemctl show -P MainPID probeless)
  check "it runs as user probeless" test "$(stat -c %U /proc/$pid)" = probeless
  check "with no new privileges and a seccomp filter" \
    grep -Eq 'NoNewPrivs:\s+1' /proc/$pid/status
  check "... seccomp mode 2" grep -Eq 'Seccomp:\s+2' /proc/$pid/status
  check "its limits: LimitNOFILE 4096" grep -Eq 'Max open files +4096 +4096' /proc/$pid/limits
  check "MemoryMax 1G, TasksMax 256" test "$(systemctl show -P MemoryMax probeless)/$(systemctl show -P TasksMax probeless)" = 1073741824/256
  echo "VM: $(systemctl show -p MemoryCurrent -p TasksCurrent -p NRestarts probeless | tr '\n' ' ')"
  # Asked until it answers with a frame out (up to 2 min): under TCG beside a loaded host one
  # answer took more than 10 s (suite run, 2026-11-27), which says nothing about the unit.
  start=$(date +%s)
  for i in $(seq 1 24); do
    status=$(curl -sf --max-time 30 http://127.0.0.1:8080/status || echo '{}')
    jq -e '.frames.out >= 1' <<<"$status" >/dev/null && break
    (($(date +%s) - start < 120)) || break
    sleep 2
  done
  echo "VM: /status after $(($(date +%s) - start)) s"
  check "/status answers: $(jq -c '{state, frames}' <<<"$status")" \
    jq -e '.frames.out >= 1 and .sources.rgbd.name == "openni2:Dummy"' <<<"$status"
  systemctl stop probeless.service

  # 2. Socket activation.
  systemctl start probeless.socket
  check "probeless.socket listens, the service is stopped" \
    test "$(systemctl is-active probeless.socket)/$(systemctl is-active probeless.service || true)" = active/inactive
  start=$(date +%s.%N)
  status=$(curl -sf --max-time 240 http://127.0.0.1:8080/status || echo '{}')
  echo "VM: first answer through the socket after $(echo "$(date +%s.%N) - $start" | bc) s"
  check "a request to the socket started the service: $(jq -c '{state}' <<<"$status")" \
    jq -e '.sources.rgbd.name == "openni2:Dummy"' <<<"$status"
  check "which serves the socket systemd passed" \
    sh -c 'journalctl -u probeless.service -b | grep -q "serving the socket systemd passed"'
  systemctl stop probeless.service probeless.socket

  # 3. The output directory under the sandbox.
  config '[output]' 'dir = "/srv/probeless-frames"'
  systemctl reset-failed probeless.service || true
  systemctl start probeless.service && code=0 || code=$?
  check "an [output] dir outside the state directory fails the start" test "$code" != 0
  journalctl -u probeless.service -b --no-pager | grep -m1 "not writable" || true
  check "... saying so in the journal" \
    sh -c 'journalctl -u probeless.service -b | grep -q "/srv/probeless-frames is not writable"'
  config '[output]' 'dir = "/var/lib/probeless/frames"' 'max_mb = 1'
  systemctl reset-failed probeless.service || true
  systemctl start probeless.service && code=0 || code=$?
  # Up to a minute for the first frames: under TCG beside a loaded host the Dummy device can
  # stall at start and be reopened (drivers/openni2, docs/drivers.md "States and recovery").
  for _ in $(seq 60); do test -s /var/lib/probeless/frames/frames.txt && break; sleep 1; done
  check "[output] dir under /var/lib/probeless is written ($(ls /var/lib/probeless/frames 2>/dev/null | wc -l) files)" \
    test -s /var/lib/probeless/frames/frames.txt
  systemctl stop probeless.service
  if ((failed > 0)); then journalctl -u probeless.service -b --no-pager | tail -40; fi
  echo "systemd unit: $passed passed, $failed failed"
  ((failed == 0))
  exit
fi

(($# == 3)) || { echo "usage: $0 SOURCE_DIR PROBELESS_BINARY CACHE_DIR" >&2; exit 2; }
src=$(realpath "$1") binary=$(realpath "$2") cache=$3
[[ -x $binary ]] || { echo "FAIL: $binary is not built"; exit 1; }
for tool in curl jq ip bc systemd-sysusers; do
  command -v $tool >/dev/null || { echo "SKIP: no $tool for the guest"; exit 77; }
done
"$here/warm_pocl_cache.sh" "$binary" "$cache/pocl-avx2" || exit $?
exec nice "$here/run_in_vm.sh" -s -m 1536M -t "${PROBELESS_VM_TIMEOUT:-600}" -- \
  "$here/check_systemd_unit.sh" --in-guest "$src" "$binary" "$(realpath "$cache/pocl-avx2")"
