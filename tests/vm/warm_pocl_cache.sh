#!/usr/bin/env bash
# Fills a PoCL kernel cache on the host for the VM tests that run the whole pipeline in a TCG
# guest (check_board_run.sh, check_systemd_unit.sh). PoCL keys its cache by the LLVM CPU its
# kernel library targets; the guest (QEMU's `-cpu max`: AVX2, no AVX-512) picks "avx2"
# (LLVM's "haswell"), so the host compiles with POCL_KERNELLIB_NAME=avx2: the same key, code
# the guest can run, at native speed. A cold compile of the pipeline's kernels in the guest
# took over 4 minutes (2026-11-26, a loaded 2-core host); this takes ~20 s once, then the
# marker file keeps it. The runs cover the RGB-D side at the VM rig's 320x240 (OpenNI2's
# Dummy device) and the light stages (the sim's rig), with the shipped config's scene: its
# PRT bake (XDG_CACHE_HOME/probeless/prt) took 107 s under TCG and is cached here too.
# Usage: warm_pocl_cache.sh PROBELESS_BINARY CACHE_DIR
set -euo pipefail
binary=$1 cache=$2
config=$(cd "$(dirname "$0")/../.." && pwd)/systemd/probeless.toml
marker=$cache/.warm-$(stat -c %Y "$binary")
[[ -f $marker ]] && exit 0
mkdir -p "$cache"
start=$(date +%s)
# Each run until its first frame is out (every program is built by then), then SIGTERM: the
# Dummy device may stall on a busy host, and the frames themselves do not matter here.
for source in "openni2:Dummy?size=320x240&hotplug=0" "sim:realtime=0"; do
  POCL_KERNELLIB_NAME=avx2 POCL_CACHE_DIR=$cache XDG_CACHE_HOME=$cache/xdg \
    nice "$binary" run --config "$config" --port 0 --source "$source" >"$cache/warm.log" 2>&1 &
  pid=$!
  for _ in $(seq 1 600); do
    grep -q "first frame out" "$cache/warm.log" && break
    kill -0 $pid 2>/dev/null || break
    sleep 0.5
  done
  kill -TERM $pid 2>/dev/null || true
  wait $pid || true
  grep -q "first frame out" "$cache/warm.log" || {
    echo "FAIL: warming PoCL's cache with $source:"; cat "$cache/warm.log"; exit 1; }
done
rm -f "$cache"/.warm-*
touch "$marker"
echo "PoCL cache warmed in $(($(date +%s) - start)) s ($cache)"
