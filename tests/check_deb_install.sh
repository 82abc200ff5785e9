#!/usr/bin/env bash
# The .deb on a clean Debian 12 (issue #7, docs/appliance.md): package the build with CPack,
# debootstrap a minimal bookworm, install the package with apt (dependencies from Debian's
# archive), and start the service as its own non-root user on the sim. A machine without
# debootstrap or the archive skips with the reason.
# Usage: check_deb_install.sh BUILD_DIR SCRATCH_DIR
set -euo pipefail
build=$(realpath "$1")
scratch=$2
mirror=${PROBELESS_DEBIAN_MIRROR:-http://deb.debian.org/debian}

skip() { echo "SKIP: $*"; exit 0; }
[[ $(id -u) == 0 ]] || skip "needs root (debootstrap, chroot)"
command -v debootstrap >/dev/null || skip "debootstrap is not installed (scripts/setup.sh)"
if ldd "$build/app/probeless" | grep -q libasan; then
  skip "a sanitizer build is not packaged (libasan is not in the chroot)"
fi

rm -rf "$scratch" && mkdir -p "$scratch"
root=$scratch/root
cleanup() {
  for m in dev/pts dev sys proc; do umount -l "$root/$m" 2>/dev/null || true; done
  rm -rf "$scratch"
}
trap cleanup EXIT

cpack --config "$build/CPackConfig.cmake" -B "$scratch/deb" >/dev/null
deb=$(ls "$scratch"/deb/probeless_*.deb)
echo "package: $(basename "$deb") ($(du -h "$deb" | cut -f1))"
# The appliance package's OpenCV is what marker anchoring links (issue #17, docs/appliance.md
# "OpenCV in the appliance"): core, imgproc, calib3d and aruco (in -contrib); the lab's package
# carries the rest (issue #16).
ls "$scratch"/deb/probeless-lab_*.deb >/dev/null || { echo "FAIL: no probeless-lab package"; exit 1; }
opencv_deps=$(dpkg-deb -f "$deb" Depends | grep -o 'libopencv-[a-z0-9]*' | sort -u | tr '\n' ' ')
[ "$opencv_deps" = "libopencv-calib3d406 libopencv-contrib406 libopencv-core406 libopencv-imgproc406 " ] ||
  { echo "FAIL: the appliance package's OpenCV dependencies are [$opencv_deps]"; exit 1; }
dpkg-deb -c "$deb" | grep -q probeless-lab && { echo "FAIL: the lab binary is in the appliance package"; exit 1; }

if ! debootstrap --variant=minbase bookworm "$root" "$mirror" >"$scratch/debootstrap.log" 2>&1; then
  tail -3 "$scratch/debootstrap.log"
  skip "debootstrap could not reach $mirror"
fi
cp "$deb" "$root/tmp/"
chroot "$root" sh -c "apt-get update -qq && DEBIAN_FRONTEND=noninteractive \
  apt-get install -y -qq --no-install-recommends /tmp/$(basename "$deb")" >"$scratch/apt.log" 2>&1 ||
  {
    tail -20 "$scratch/apt.log"
    if grep -Eq "Failed to fetch|Could not resolve|Temporary failure|Unable to connect" \
      "$scratch/apt.log"; then skip "the Debian archive went away during the install"; fi
    echo "FAIL: apt could not install the package"; exit 1
  }

# What the package set up.
chroot "$root" id probeless
for group in video render gpio plugdev; do
  chroot "$root" id -nG probeless | tr ' ' '\n' | grep -qx "$group" ||
    { echo "FAIL: probeless is not in $group"; exit 1; }
done
for f in /usr/bin/probeless /usr/lib/systemd/system/probeless.service \
  /usr/lib/sysusers.d/probeless.conf /usr/lib/udev/rules.d/60-probeless.rules \
  /etc/probeless/probeless.toml; do
  [[ -e $root$f ]] || { echo "FAIL: $f not installed"; exit 1; }
done
for m in $(chroot "$root" ldd /usr/bin/probeless | grep -o 'libopencv_[a-z0-9_]*' | sort -u); do
  case $m in libopencv_aruco|libopencv_calib3d|libopencv_core|libopencv_imgproc|\
    libopencv_features2d|libopencv_flann) ;;
    *) echo "FAIL: the installed service loads $m"; exit 1 ;;
  esac
done
[[ -L $root/etc/systemd/system/multi-user.target.wants/probeless.service ]] ||
  { echo "FAIL: the service is not enabled"; exit 1; }

# The unit's command as systemd would start it (no systemd runs in a chroot): its user, its
# Environment= lines, the directories CacheDirectory=/StateDirectory= would make, the shipped
# config (the sim: no sensor here).
mount -t proc proc "$root/proc"
mount --rbind /sys "$root/sys"
mount --rbind /dev "$root/dev"
unit=$root/usr/lib/systemd/system/probeless.service
mapfile -t unit_env < <(sed -n 's/^Environment=//p' "$unit" | sed 's|%C|/var/cache|g')
command=$(sed -n 's/^ExecStart=//p' "$unit")
chroot "$root" install -d -o probeless -g probeless /var/cache/probeless /var/lib/probeless
out=$(chroot "$root" setpriv --reuid=probeless --regid=probeless --init-groups \
  env HOME=/var/lib/probeless CACHE_DIRECTORY=/var/cache/probeless \
  STATE_DIRECTORY=/var/lib/probeless "${unit_env[@]}" \
  $command --frames 10 --port 0 2>&1) ||
  { echo "$out"; echo "FAIL: the installed service did not run"; exit 1; }
grep -q "first frame out" <<<"$out" || { echo "$out"; echo "FAIL: no frame out"; exit 1; }
grep -q "rgbd streaming" <<<"$out" || { echo "$out"; echo "FAIL: no streaming source"; exit 1; }
echo "installed package runs as probeless on the sim: OK"
