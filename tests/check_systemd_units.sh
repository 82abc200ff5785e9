#!/usr/bin/env bash
# The appliance's systemd and udev files (systemd/, docs/appliance.md), checked with systemd's
# own tools: the unit verifies, its sandbox scores <= 2.5 in `systemd-analyze security`, the
# sysusers and tmpfiles files apply to a scratch root, the udev rules parse.
# Usage: check_systemd_units.sh SOURCE_DIR PROBELESS_BINARY
set -euo pipefail
src=$1/systemd
binary=$2
max_exposure=2.5

if ! command -v systemd-analyze >/dev/null; then
  echo "SKIP: systemd-analyze is not installed"; exit 0
fi
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

# verify needs ExecStart's binary to exist: point it at the build's.
sed "s|^ExecStart=/usr/bin/probeless|ExecStart=$binary|" "$src/probeless.service" \
  >"$scratch/probeless.service"
cp "$src/probeless.socket" "$scratch/"
systemd-analyze verify --man=no "$scratch/probeless.service" "$scratch/probeless.socket"
# The limits of issue #20, each justified in the unit and docs/appliance.md "Limits".
for key in StartLimitIntervalSec StartLimitBurst LimitNOFILE MemoryMax TasksMax; do
  grep -q "^$key=" "$src/probeless.service" || { echo "FAIL: no $key= in probeless.service"; exit 1; }
done

report=$(systemd-analyze security --offline=true --no-pager "$scratch/probeless.service")
exposure=$(sed -n 's/.*Overall exposure level for probeless.service: \([0-9.]*\).*/\1/p' <<<"$report")
if [[ -z $exposure ]]; then
  echo "FAIL: no exposure level in:"; echo "$report"; exit 1
fi
echo "systemd-analyze security: exposure $exposure (bar $max_exposure)"
awk -v e="$exposure" -v m="$max_exposure" 'BEGIN { exit !(e <= m) }' || {
  echo "FAIL: exposure $exposure above $max_exposure"; grep '✗' <<<"$report"; exit 1; }

# sysusers and tmpfiles on a copy of this machine's user database.
mkdir -p "$scratch/root/etc"
cp /etc/passwd /etc/group "$scratch/root/etc/"
touch "$scratch/root/etc/shadow" "$scratch/root/etc/gshadow"
systemd-sysusers --root="$scratch/root" "$src/probeless.sysusers" >/dev/null 2>&1
grep -q '^probeless:' "$scratch/root/etc/passwd" || { echo "FAIL: no probeless user"; exit 1; }
for group in video render gpio plugdev; do
  grep -Eq "^$group:[^:]*:[0-9]+:(.*,)?probeless(,|$)" "$scratch/root/etc/group" ||
    { echo "FAIL: probeless is not in group $group"; exit 1; }
done
systemd-tmpfiles --root="$scratch/root" --create "$src/probeless.tmpfiles"
[[ -d $scratch/root/etc/probeless ]] || { echo "FAIL: tmpfiles made no /etc/probeless"; exit 1; }

# udev rules: every rule line is KEY op "VALUE" pairs (udevadm verify arrives in systemd 254).
bad=$(grep -Ev '^\s*(#|$)' "$src/60-probeless.rules" |
  grep -Ev '^([A-Za-z_]+(\{[A-Za-z_]+\})?(==|!=|=|\+=|:=)"[^"]*"(, )?)+$' || true)
if [[ -n $bad ]]; then echo "FAIL: malformed udev rule:"; echo "$bad"; exit 1; fi
for vendor in 1d27 045e 2bc5; do
  grep -q "ATTR{idVendor}==\"$vendor\"" "$src/60-probeless.rules" ||
    { echo "FAIL: no rule for USB vendor $vendor"; exit 1; }
done
echo "systemd units OK"
