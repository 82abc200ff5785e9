#!/usr/bin/env bash
# The arrows of docs/architecture.md "Layers":
#   base     includes nothing of ours (OS utilities: fds, atomic files, hashing, stats, slots)
#   core     includes core only (types and maths: no I/O, so not even base)
#   drivers  core and base, never kernels (nor anything above)
#   kernels  core and base, never drivers (nor anything above)
#   app      everything below it, never the lab
#   lab      anything (evaluators, benches, datasets, the OpenCV reference)
# and the synthetic rig stays out of the appliance: only drivers/sim itself, the rig factory
# that opens it by name (drivers/rig_factory.cpp), the lab and the tests include drivers/sim.
# Usage: check_layering.sh [ROOT]; exit 1 with the offending lines on a violation.
set -u
root=${1:-.}
cd "$root" || exit 2
fail=0
includes() {  # includes <dir> <prefix>: the lines in <dir> that include <prefix>/...
  grep -rnE "#include [\"<]$2/" "$1" --include='*.hpp' --include='*.cpp' --include='*.h' \
    --include='*.cl' 2>/dev/null
}
check() {  # check <dir> <forbidden include prefix...>
  local dir=$1; shift
  [ -d "$dir" ] || return 0
  for bad in "$@"; do
    hits=$(includes "$dir" "$bad")
    if [ -n "$hits" ]; then echo "layering: $dir must not include $bad/:"; echo "$hits"; fail=1; fi
  done
}
check base core drivers kernels app lab
check core base drivers kernels app lab
check drivers kernels app lab
check kernels drivers app lab
check app lab
# drivers/sim: allowed in drivers/sim, drivers/rig_factory.cpp, lab/ and tests/ only.
for dir in base core drivers kernels app; do
  [ -d "$dir" ] || continue
  hits=$(includes "$dir" "drivers/sim" | grep -vE '^drivers/sim/|^drivers/rig_factory\.cpp:')
  if [ -n "$hits" ]; then
    echo "layering: only drivers/sim, drivers/rig_factory.cpp, lab/ and tests/ include drivers/sim:"
    echo "$hits"; fail=1
  fi
done
[ $fail -eq 0 ] && echo "layering: ok"
exit $fail
