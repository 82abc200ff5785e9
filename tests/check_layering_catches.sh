#!/usr/bin/env bash
# check_layering.sh must fail on each kind of wrong include (a check that cannot fail is a
# defect): plant one at a time in a copy of the source folders and expect exit 1.
# Usage: check_layering_catches.sh SOURCE_ROOT
set -u
src=$(cd "$1" && pwd)
check=$src/tests/check_layering.sh
tmp=$(mktemp -d) && trap 'rm -rf "$tmp"' EXIT
cp -r "$src"/{base,core,drivers,kernels,app,lab} "$tmp"/
"$check" "$tmp" >/dev/null || { echo "FAIL: the clean tree does not pass"; "$check" "$tmp"; exit 1; }
fail=0
plant() {  # plant <file> <include>: expect the check to fail, then remove the plant
  local file=$tmp/$1
  cp "$file" "$file.orig"
  printf '#include "%s"\n' "$2" >>"$file"
  if "$check" "$tmp" >/dev/null; then echo "FAIL: not caught: $1 including $2"; fail=1; fi
  mv "$file.orig" "$file"
}
first() { (cd "$tmp" && ls "$1"/*.cpp "$1"/*/*.cpp 2>/dev/null | head -1); }
plant "$(first base)" core/pose.hpp
plant "$(first core)" base/unique_fd.hpp
plant "$(first drivers)" kernels/runtime/compute_context.hpp
plant "$(first kernels)" drivers/source.hpp
plant "$(first app)" lab/eval/method_set.hpp
plant "$(first app)" drivers/sim/sim_rig.hpp
plant "$(first kernels)" drivers/sim/sim_rig.hpp
plant "$(first drivers/replay)" drivers/sim/sim_rig.hpp
[ $fail -eq 0 ] && echo "layering check catches every planted include: ok"
exit $fail
