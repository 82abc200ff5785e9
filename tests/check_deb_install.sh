#!/usr/bin/env bash
# The Debian packages on a clean Debian 12 (issues #7 and #22, docs/appliance.md "The Debian
# packages"): package the build tree with debian/rules (no second compile), check the two
# packages (lintian, the split, the maintainer scripts), debootstrap a minimal bookworm,
# install the appliance with apt (dependencies from Debian's archive), start the service as
# its own non-root user on the sim, then upgrade it with the unit disabled and check that it
# stays disabled. A machine without root, debootstrap, debhelper or the archive skips with
# the reason.
# Usage: check_deb_install.sh SOURCE_DIR BUILD_DIR SCRATCH_DIR PROJECT_VERSION
set -euo pipefail
src=$(realpath "$1")
build=$(realpath "$2")
scratch=$3
version=$4
mirror=${PROBELESS_DEBIAN_MIRROR:-http://deb.debian.org/debian}

skip() { echo "SKIP: $*"; exit 0; }
fail() { echo "FAIL: $*"; exit 1; }
[[ $(id -u) == 0 ]] || skip "needs root (debootstrap, chroot)"
command -v debootstrap >/dev/null || skip "debootstrap is not installed (scripts/setup.sh)"
for tool in dpkg-buildpackage dh lintian; do
  command -v $tool >/dev/null || skip "$tool is not installed (scripts/setup.sh)"
done
if ldd "$build/app/probeless" | grep libasan >/dev/null; then
  skip "a sanitizer build is not packaged (libasan is not in the chroot)"
fi

rm -rf "$scratch" && mkdir -p "$scratch"
root=$scratch/root
cleanup() {
  for m in dev/pts dev sys proc; do umount -l "$root/$m" 2>/dev/null || true; done
  rm -rf "$scratch"
}
trap cleanup EXIT

# Package from a copy of debian/ (and systemd/, which its unit, sysusers, tmpfiles and udev
# files link to): dpkg-buildpackage writes debian/tmp and the package trees beside
# debian/rules, and the checkout is not the test's to write to (two build trees' tests would
# share one debian/tmp). The install rules still read the checkout's files.
mkdir -p "$scratch/src" "$scratch/deb"
cp -a "$src/debian" "$src/systemd" "$scratch/src/"
arch=$(dpkg --print-architecture)
if ! (cd "$scratch/src" && PROBELESS_BUILD_DIR=$build PROBELESS_DEB_DIR=$scratch/deb \
  dpkg-buildpackage -b --no-sign \
  --changes-option=-u"$scratch/deb" --buildinfo-option=-u"$scratch/deb" \
  --changes-file="$scratch/deb/probeless_${version}_$arch.changes" \
  --buildinfo-file="$scratch/deb/probeless_${version}_$arch.buildinfo") \
  >"$scratch/dpkg-buildpackage.log" 2>&1; then
  tail -30 "$scratch/dpkg-buildpackage.log"
  fail "dpkg-buildpackage could not package $build"
fi
# Packaging must not have compiled anything (the tree was built by the test's build).
if grep -Eq '^\[[0-9]+/[0-9]+\] (Building|Linking)' "$scratch/dpkg-buildpackage.log"; then
  grep -E '^\[[0-9]+/[0-9]+\]' "$scratch/dpkg-buildpackage.log" | head -5
  fail "debian/rules compiled instead of only packaging $build (out of date? build it first)"
fi
deb=$scratch/deb/probeless_${version}_$arch.deb
lab=$scratch/deb/probeless-lab_${version}_$arch.deb
[[ -f $deb ]] || fail "no $(basename "$deb") (debian/changelog's version is not $version?)"
[[ -f $lab ]] || fail "no $(basename "$lab")"
echo "packages: $(basename "$deb") ($(du -h "$deb" | cut -f1)), $(basename "$lab") ($(du -h "$lab" | cut -f1))"

# lintian: no errors. Warnings and overrides are listed in docs/appliance.md.
lintian --show-overrides "$deb" "$lab" >"$scratch/lintian.log" 2>&1 || true
grep -v '^N:' "$scratch/lintian.log" | grep -v 'running with root privileges' || true
if grep -q '^E:' "$scratch/lintian.log"; then fail "lintian reports errors"; fi
echo "lintian: no errors ($(grep -c '^W:' "$scratch/lintian.log" || true) warnings," \
  "$(grep -c '^O:' "$scratch/lintian.log" || true) overridden)"

# The split (issue #16): the lab binary in the lab's package only; the appliance's OpenCV is
# what marker anchoring links (issue #17, docs/appliance.md "OpenCV in the appliance"):
# core, imgproc, calib3d and aruco (in -contrib).
# (The listings are read whole: `dpkg-deb -c | grep -q` dies of SIGPIPE under pipefail.)
deb_files=$(dpkg-deb -c "$deb")
lab_files=$(dpkg-deb -c "$lab")
grep -q 'usr/lib/probeless/probeless-lab' <<<"$deb_files" &&
  fail "the lab binary is in the appliance package"
grep -q '\./usr/lib/probeless/probeless-lab$' <<<"$lab_files" ||
  fail "the lab package has no /usr/lib/probeless/probeless-lab"
opencv_deps=$(dpkg-deb -f "$deb" Depends | grep -o 'libopencv-[a-z0-9]*' | sort -u | tr '\n' ' ')
[ "$opencv_deps" = "libopencv-calib3d406 libopencv-contrib406 libopencv-core406 libopencv-imgproc406 " ] ||
  fail "the appliance package's OpenCV dependencies are [$opencv_deps]"
grep -q "probeless (= $version)" <<<"$(dpkg-deb -f "$lab" Depends)" ||
  fail "probeless-lab does not depend on probeless (= $version)"

# The maintainer scripts. The config is a conffile (an admin's edits survive upgrades).
mkdir -p "$scratch/control"
dpkg-deb -e "$deb" "$scratch/control"
grep -qx /etc/probeless/probeless.toml "$scratch/control/conffiles" ||
  fail "/etc/probeless/probeless.toml is not a conffile"
# Every udevadm trigger is filtered (no replay of every device on the machine), and it names
# the devices of systemd/60-probeless.rules: vendor:product, or vendor: for a whole vendor.
if grep 'udevadm trigger' "$scratch/control/postinst" | grep -v -- '--subsystem-match'; then
  fail "postinst runs udevadm trigger without --subsystem-match"
fi
rules_devices=$(sed -n 's/.*ATTR{idVendor}=="\([0-9a-f]*\)".*/\1/p' "$src/systemd/60-probeless.rules" |
  sort -u | while read -r v; do
    products=$(sed -n "s/.*ATTR{idVendor}==\"$v\".*ATTR{idProduct}==\"\\([0-9a-f|]*\\)\".*/\\1/p" \
      "$src/systemd/60-probeless.rules")
    if [[ -z $products ]]; then echo "$v:"; else tr '|' '\n' <<<"$products" | sed "s/^/$v:/"; fi
  done | sort | tr '\n' ' ')
postinst_devices=$(sed -n 's/^ *for device in \(.*\); do$/\1/p' "$scratch/control/postinst" |
  tr ' ' '\n' | sort | tr '\n' ' ')
[[ $rules_devices == "$postinst_devices" ]] ||
  fail "postinst triggers [$postinst_devices], the udev rules name [$rules_devices]"

if ! debootstrap --variant=minbase bookworm "$root" "$mirror" >"$scratch/debootstrap.log" 2>&1; then
  tail -3 "$scratch/debootstrap.log"
  skip "debootstrap could not reach $mirror"
fi
# apt_install LOG PACKAGE_FILE [APT_ARGS...]: install a .deb in the chroot; a failure to reach
# the archive skips, any other fails.
apt_install() {
  local log=$1 file=$2; shift 2
  cp "$file" "$root/tmp/"
  chroot "$root" sh -c "DEBIAN_FRONTEND=noninteractive apt-get install -y -qq \
    --no-install-recommends $* /tmp/$(basename "$file")" >"$log" 2>&1 ||
    {
      tail -20 "$log"
      if grep -Eq "Failed to fetch|Could not resolve|Temporary failure|Unable to connect" "$log"; then
        skip "the Debian archive went away during the install"
      fi
      fail "apt could not install $(basename "$file")"
    }
}
chroot "$root" apt-get update -qq >"$scratch/apt-update.log" 2>&1 ||
  { tail -5 "$scratch/apt-update.log"; skip "apt-get update could not reach $mirror"; }
apt_install "$scratch/apt.log" "$deb"

# What the package set up.
chroot "$root" id probeless
for group in video render gpio plugdev; do
  chroot "$root" id -nG probeless | tr ' ' '\n' | grep -qx "$group" ||
    fail "probeless is not in $group"
done
# Where debhelper 13 puts them (/lib is /usr/lib on a merged-/usr bookworm).
for f in /usr/bin/probeless /lib/systemd/system/probeless.service \
  /lib/systemd/system/probeless.socket /usr/lib/sysusers.d/probeless.conf \
  /usr/lib/tmpfiles.d/probeless.conf /lib/udev/rules.d/60-probeless.rules \
  /etc/probeless/probeless.toml /usr/share/probeless/board /usr/share/doc/probeless/README.md; do
  [[ -e $root$f ]] || fail "$f not installed"
done
[[ -e $root/usr/lib/probeless/probeless-lab ]] && fail "the lab binary came with the appliance"
for m in $(chroot "$root" ldd /usr/bin/probeless | grep -o 'libopencv_[a-z0-9_]*' | sort -u); do
  case $m in libopencv_aruco|libopencv_calib3d|libopencv_core|libopencv_imgproc|\
    libopencv_features2d|libopencv_flann) ;;
    *) fail "the installed service loads $m" ;;
  esac
done
wants=$root/etc/systemd/system/multi-user.target.wants/probeless.service
[[ -L $wants ]] || fail "the service is not enabled on the first install"
[[ -e $root/etc/systemd/system/sockets.target.wants/probeless.socket ]] &&
  fail "the package enabled probeless.socket (it is the admin's to enable)"

# The unit's command as systemd would start it (no systemd runs in a chroot): its user, its
# Environment= lines, the directories CacheDirectory=/StateDirectory= would make, the shipped
# config (the sim: no sensor here).
mount -t proc proc "$root/proc"
mount --rbind /sys "$root/sys"
mount --rbind /dev "$root/dev"
unit=$root/lib/systemd/system/probeless.service
mapfile -t unit_env < <(sed -n 's/^Environment=//p' "$unit" | sed 's|%C|/var/cache|g')
command=$(sed -n 's/^ExecStart=//p' "$unit")
chroot "$root" install -d -o probeless -g probeless /var/cache/probeless /var/lib/probeless
out=$(chroot "$root" setpriv --reuid=probeless --regid=probeless --init-groups \
  env HOME=/var/lib/probeless CACHE_DIRECTORY=/var/cache/probeless \
  STATE_DIRECTORY=/var/lib/probeless "${unit_env[@]}" \
  $command --frames 10 --port 0 2>&1) ||
  { echo "$out"; fail "the installed service did not run"; }
grep -q "first frame out" <<<"$out" || { echo "$out"; fail "no frame out"; }
grep -q "rgbd streaming" <<<"$out" || { echo "$out"; fail "no streaming source"; }
echo "installed package runs as probeless on the sim: OK"

# An admin's disable survives an upgrade and a reinstall (the CPack postinst enabled the unit
# again on every upgrade). systemctl works on the unit files without a running systemd; the
# upgrade is the same package with a higher version, so postinst runs with the old version in
# $2 as in a real upgrade.
# deb-systemd-helper records the links it made and answers `was-enabled` from them, which
# is what postinst asks; it runs only under dpkg (DPKG_MAINTSCRIPT_PACKAGE set), so the
# question is asked here as postinst would, and first while enabled, so that a query that
# fails cannot pass for "disabled".
was_enabled() {
  chroot "$root" env DPKG_MAINTSCRIPT_PACKAGE=probeless \
    deb-systemd-helper --quiet was-enabled probeless.service
}
was_enabled || fail "deb-systemd-helper does not record the enabled unit as enabled"
chroot "$root" systemctl disable probeless.service >"$scratch/disable.log" 2>&1 ||
  { cat "$scratch/disable.log"; fail "systemctl disable failed in the chroot"; }
[[ -L $wants ]] && fail "systemctl disable left the unit enabled"
was_enabled && fail "deb-systemd-helper records the disabled unit as enabled"
mkdir -p "$scratch/upgrade"
dpkg-deb -R "$deb" "$scratch/upgrade/tree"
sed -i "s/^Version: .*/Version: $version+upgradetest1/" "$scratch/upgrade/tree/DEBIAN/control"
upgrade=$scratch/upgrade/probeless_${version}+upgradetest1_$arch.deb
dpkg-deb -b "$scratch/upgrade/tree" "$upgrade" >/dev/null
apt_install "$scratch/apt-upgrade.log" "$upgrade"
[[ $(chroot "$root" dpkg-query -W -f '${Version}' probeless) == "$version+upgradetest1" ]] ||
  fail "the upgrade was not installed"
still_disabled() {  # still_disabled WHAT
  [[ -L $wants ]] && fail "the $1 enabled the unit the admin disabled"
  was_enabled && fail "after the $1 deb-systemd-helper records the unit as enabled"
  return 0
}
still_disabled upgrade
apt_install "$scratch/apt-reinstall.log" "$upgrade" --reinstall
still_disabled reinstall
echo "a disabled unit stays disabled across an upgrade and a reinstall: OK"
