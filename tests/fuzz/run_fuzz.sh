#!/bin/sh
# Runs every libFuzzer target of the `fuzz` preset for SECONDS each (`make fuzz`,
# docs/fuzzing.md). Usage: run_fuzz.sh BUILD_DIR SECONDS [TARGET...]
# FUZZ_RUNS=N in the environment: stop a target after N inputs instead, if that comes first
# (issue #20's bar is 1,000,000 per target).
# Each target starts from its seeds (tests/fuzz/corpus/<name>/) and what earlier runs found
# (BUILD_DIR/corpus/<name>/, kept between runs, never in the repository). A crash, leak,
# sanitizer report, timeout or out-of-memory leaves its input in BUILD_DIR/crashes/<name>/;
# all targets run, and the script then exits 1 if any of them failed.
set -u
build=$1
seconds=$2
shift 2
source_dir=$(cd "$(dirname "$0")" && pwd)
list="$build/tests/fuzz/targets.txt"
[ -f "$list" ] || { echo "$list missing: build the fuzz preset first" >&2; exit 2; }
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:use_sigaltstack=0}"
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$source_dir/../lsan.supp:print_suppressions=0}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
failed=""
while read -r name max_len; do
  if [ $# -gt 0 ]; then
    case " $* " in *" $name "*) ;; *) continue ;; esac
  fi
  corpus="$build/corpus/$name"
  crashes="$build/crashes/$name"
  mkdir -p "$corpus" "$crashes"
  log="$build/logs/$name.log"
  mkdir -p "$build/logs"
  echo "== $name: ${seconds} s, -max_len=$max_len"
  # -timeout: a parser that takes 10 s over one input of a few KB hangs;
  # -rss_limit_mb, -malloc_limit_mb: a reader that holds 1.5 GB, or asks for 512 MB at once,
  # for such an input lacks a size check (ASan's own overhead is ~150-300 MB here).
  if "$build/tests/fuzz/${name}_fuzz" -max_total_time="$seconds" -max_len="$max_len" \
      ${FUZZ_RUNS:+-runs="$FUZZ_RUNS"} \
      -timeout=10 -rss_limit_mb=1536 -malloc_limit_mb=512 -print_final_stats=1 \
      -artifact_prefix="$crashes/" "$corpus" "$source_dir/corpus/$name" >"$log" 2>&1; then
    # One line per target for docs/fuzzing.md: inputs run, their rate, the coverage
    # (edges, features) and corpus size of the last status line, and the peak memory.
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
    rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log")
    rss=$(sed -n 's/^stat::peak_rss_mb: *//p' "$log")
    last=$(grep -E '^#[0-9]+' "$log" | tail -1)
    cov=$(echo "$last" | sed -n 's/.* cov: \([0-9]*\).*/\1/p')
    ft=$(echo "$last" | sed -n 's/.* ft: \([0-9]*\).*/\1/p')
    corp=$(echo "$last" | sed -n 's/.* corp: \([0-9]*\/[0-9a-zA-Z]*\).*/\1/p')
    echo "RESULT $name execs=$execs exec_per_s=$rate cov=$cov ft=$ft corpus=$corp peak_rss_mb=$rss"
  else
    echo "FAILED: $name (log $log, input in $crashes/)"
    grep -E 'ERROR|SUMMARY|runtime error|Test unit written' "$log" | head -5
    failed="$failed $name"
  fi
done <"$list"
if [ -n "$failed" ]; then
  echo "fuzz targets that failed:$failed"
  exit 1
fi
