#!/usr/bin/env bash
# The arrows of docs/architecture.md: core includes nothing of ours but core; drivers and
# kernels include core only (never each other); only app joins them.
set -u
root=${1:-.}
cd "$root" || exit 2
fail=0
check() {  # check <dir> <forbidden include prefix...>
  local dir=$1; shift
  for bad in "$@"; do
    hits=$(grep -rnE "#include [\"<]${bad}/" "$dir" --include='*.hpp' --include='*.cpp' --include='*.h' 2>/dev/null)
    if [ -n "$hits" ]; then echo "layering: $dir must not include $bad/:"; echo "$hits"; fail=1; fi
  done
}
check core drivers kernels app
check drivers kernels app
check kernels drivers app
[ $fail -eq 0 ] && echo "layering: ok"
exit $fail
