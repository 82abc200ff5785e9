#!/usr/bin/env bash
# Installs the Debian packages in scripts/packages.txt that are not installed yet.
# Idempotent: on a machine that has them all it only checks and returns.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
mapfile -t wanted < <(sed -e 's/#.*//' -e 's/[[:space:]]//g' "$here/packages.txt" | grep -v '^$')
# A name without ":arch" means the native package (or an "all" one); with several
# architectures installed dpkg-query prints one line per instance.
native=$(dpkg --print-architecture)
missing=()
for p in "${wanted[@]}"; do
  [[ $p == *:* ]] && want="${p#*:}" || want="$native|all"
  dpkg-query -W -f='${Architecture} ${Status}\n' "$p" 2>/dev/null |
    grep -Eq "^($want) install ok installed$" || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  echo "setup: all ${#wanted[@]} packages present"
  exit 0
fi
echo "setup: installing ${#missing[@]} missing packages: ${missing[*]}"
sudo=""
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "setup: not root and no sudo; install: ${missing[*]}" >&2; exit 1; }
  sudo="sudo"
fi
# "name:arch" entries (the arm64 cross build's libraries) need dpkg to know that architecture
# (multiarch); adding one that is already there is skipped, so a second run changes nothing.
for arch in $(printf '%s\n' "${missing[@]}" | sed -n 's/^[^:]*:\([a-z0-9]*\)$/\1/p' | sort -u); do
  if [[ $arch != "$(dpkg --print-architecture)" ]] &&
    ! dpkg --print-foreign-architectures | grep -qx "$arch"; then
    echo "setup: adding the $arch architecture (dpkg --add-architecture)"
    $sudo dpkg --add-architecture "$arch"
  fi
done
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -q
$sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
