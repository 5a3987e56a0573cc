#!/usr/bin/env bash
# Builds the libFuzzer targets of fuzz/ in build-fuzz/ (clang, ASan, UBSan) and runs each one
# after the other, printing its executions and executions per second (docs/fuzzing.md).
#
#   scripts/fuzz.sh [-t seconds | -r runs] [-s seed] [-f] [-j jobs] [-b build] [target ...]
#
#   -t seconds  run each target for this long (-max_total_time; default 60)
#   -r runs     run each target for this many inputs (-runs) instead
#   -s seed     libFuzzer's -seed (default: a random one, printed in each log); the same seed
#               from the same corpus replays the same inputs in the same order
#   -f          from the seed corpus alone, as a fresh clone (CI) runs: the work folder is
#               <build>/fuzz-smoke-corpus/<target>/, emptied first
#   -j jobs     build parallelism (default 2)
#   -b build    build folder (default build-fuzz; any clang build folder configured with
#               the fuzz targets); configured here when absent
#   target      campaign test_yaml signals uff58 frf_text matfile inspections (default: all)
#
# Each target starts from its seed corpus fuzz/corpus/<target>/ (read only) and keeps what it
# finds in <build>/fuzz-corpus/<target>/ (with -f: see above); crashes go to
# <build>/fuzz-artifacts/<target>/. Each run adds a line to <build>/fuzz-history.tsv (times,
# target, commit, seed, corpus folder, executions, exec/s, and ok, FAILED,
# timeout-not-reproduced (a timeout whose input, run once more alone, finishes in time) or
# interrupted (the fuzzer stopped with SIGINT, e.g. Ctrl-C: the targets after it are not run).
# Runs under nice -n 19, one target at a time. Exit status 1 when a target failed; then the
# end of the output names the finding (libFuzzer's and the sanitizer's summary lines, the top
# of the stack) and gives the saved input in base64, so that a failure in CI, whose build
# folder is gone, can be replayed (docs/fuzzing.md, "When a run fails").
set -euo pipefail

root="$(cd "$(dirname "$0")/.." && pwd)"
build="$root/build-fuzz"
seconds=60
runs=""
seed=""
fresh=""
jobs=2
while getopts "t:r:s:fj:b:h" opt; do
  case "$opt" in
    t) seconds="$OPTARG" ;;
    r) runs="$OPTARG" ;;
    s) seed="$OPTARG" ;;
    f) fresh=1 ;;
    j) jobs="$OPTARG" ;;
    b) build="$(cd "$(dirname "$OPTARG")" && pwd)/$(basename "$OPTARG")" ;;
    *) sed -n '2,25p' "$0"; exit 2 ;;
  esac
done
shift $((OPTIND - 1))
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  targets=(campaign test_yaml signals uff58 frf_text matfile inspections)
fi

if [ ! -f "$build/CMakeCache.txt" ]; then
  generator=()
  if command -v ninja >/dev/null 2>&1; then generator=(-G Ninja); fi
  CC=clang CXX=clang++ cmake "${generator[@]}" -S "$root" -B "$build" -DCHATTERLAB_FUZZ=ON \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -gline-tables-only" \
    -DCHATTERLAB_WERROR=OFF -DCHATTERLAB_BENCHMARKS=OFF
fi
cmake --build "$build" -j"$jobs" --target $(printf '%s_fuzz ' "${targets[@]}")
# The commit the targets were just built from, for fuzz-history.tsv: read now, not when a run
# ends (the work tree may have moved on during a run of hours).
built_commit=$(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)

# The targets write each input to a file for readers that take a path: on tmpfs when there is
# one. On ext4 the truncate-and-rewrite of that file forces a write-back each time; tmpfs made
# signals_fuzz 3.4 times faster (docs/fuzzing.md).
if [ -z "${TMPDIR:-}" ] && [ -d /dev/shm ] && [ -w /dev/shm ]; then export TMPDIR=/dev/shm; fi

status=0
summary=()
failures=()
declare -A started
for t in "${targets[@]}"; do
  work="$build/fuzz-corpus/$t"
  if [ -n "$fresh" ]; then
    work="$build/fuzz-smoke-corpus/$t"
    rm -rf "$work"
  fi
  artifacts="$build/fuzz-artifacts/$t"
  mkdir -p "$work" "$artifacts"
  # An allocation above 2 GB is a finding through ASan (max_allocation_size_mb) rather than
  # libFuzzer's malloc limit: libFuzzer's hook also runs in the child processes .mat files are
  # read in, where it would save the input as a crash of the target while the target goes on.
  # matfile's limit is 640 MB: above the 512 MB its reply string may reach (a reply is cut at
  # 256 MiB and the string grows by doubling), far above what a variable the .mat checks pass
  # can take from a 4 kB input (76 MB), and below the 1 GB libmatio callocs for a count it reads
  # from a damaged 1.5 kB v5 file. ASan clears what it allocates, so each such input took 3.2 s
  # and the kept corpus drifted to them (150 exec/s); past the limit the reader process ends at
  # once, a contained failure (docs/fuzzing.md, "Speed"). And with allocator_may_return_null,
  # libmatio's and libhdf5's malloc past it returns null, which they check, instead of ending the
  # reader process: 4 times fewer reader processes ended, 357 exec/s against 263 on the same
  # 15,000 inputs. operator new still reports past the limit, so the target's own C++ code is
  # held to it as before.
  args=(-timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=1048576 -print_final_stats=1
    "-artifact_prefix=$artifacts/")
  if [ -n "$runs" ]; then args+=("-runs=$runs"); else args+=("-max_total_time=$seconds"); fi
  if [ -n "$seed" ]; then args+=("-seed=$seed"); fi
  if [ -f "$root/fuzz/$t.dict" ]; then args+=("-dict=$root/fuzz/$t.dict"); fi
  log="$build/fuzz-$t.log"
  echo "== $t"
  started[$t]=$(date +%s)
  # matfile's reader process dies on many damaged files (libhdf5), each time with a sanitizer
  # report that is not a finding: unsymbolized, 384 exec/s instead of 238 (docs/fuzzing.md,
  # "Speed"). A finding of the target is replayed symbolized below.
  # The YAML targets run without allocation stacks: ASan's stack depot keeps every distinct
  # stack for the life of the process, and the YAML parser's recursion makes new ones for as
  # long as the run lasts (campaign_fuzz grew by about 0.7 MB per 1,000 executions with them,
  # docs/fuzzing.md "Memory"). A finding of such a run is replayed with the stacks below.
  run_opts="symbolize=1"
  alloc_mb=2048
  case "$t" in
    matfile) run_opts="symbolize=0:allocator_may_return_null=1" alloc_mb=640 ;;
    campaign | test_yaml) run_opts="symbolize=1:malloc_context_size=0" ;;
  esac
  if ASAN_OPTIONS="max_allocation_size_mb=$alloc_mb:$run_opts${ASAN_OPTIONS:+:$ASAN_OPTIONS}" \
    LSAN_OPTIONS="suppressions=$root/fuzz/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}" \
    nice -n 19 "$build/fuzz/${t}_fuzz" "${args[@]}" "$work" "$root/fuzz/corpus/$t" >"$log" 2>&1; then
    result=ok
  elif grep -q 'libFuzzer: run interrupted; exiting' "$log"; then
    # Stopped with SIGINT (Ctrl-C, or kill -INT of the fuzzer; the .mat reader processes do
    # not print this): its final stats are in the log, and the executions up to then count.
    result=interrupted
  else
    result="FAILED (see $log and $artifacts/)"
    # A timeout that its input does not repeat when run again alone is the machine's load, not
    # a hang: the runs are at nice 19, and a build at normal priority beside them can hold one
    # input past -timeout (two such runs of 4 December 2026 stopped on inputs that take 7 and
    # 27 ms; docs/fuzzing.md, "When a run fails"). The input is replayed once, here.
    input=$( (find "$artifacts" -type f -name 'timeout-*' -newermt "@${started[$t]}" \
      -printf '%T@ %p\n' 2>/dev/null | sort -n | tail -1 | cut -d' ' -f2-) || true)
    if [ -n "$input" ] &&
      ASAN_OPTIONS="max_allocation_size_mb=$alloc_mb:$run_opts${ASAN_OPTIONS:+:$ASAN_OPTIONS}" \
        LSAN_OPTIONS="suppressions=$root/fuzz/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}" \
        "$build/fuzz/${t}_fuzz" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=1048576 \
        "-artifact_prefix=$artifacts/replay-" "$input" >"$log.timeout-replay" 2>&1; then
      ms=$(sed -n 's/^Executed .* in \([0-9]*\) ms$/\1/p' "$log.timeout-replay" | tail -1)
      result="timeout-not-reproduced (the input runs in ${ms:-?} ms alone: a loaded machine;"
      result+=" see $log)"
    else
      status=1
      failures+=("$t")
    fi
  fi
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  line="$t: ${execs:-?} executions, ${rate:-?} exec/s, $result"
  echo "$line"
  summary+=("$line")
  # Every run of a target, one line each, kept across runs: the executions toward a goal such as
  # issue 16's 10 million add up over runs that continue the same kept corpus.
  history="$build/fuzz-history.tsv"
  if [ ! -f "$history" ]; then
    printf 'started\tended\ttarget\tcommit\tseed\tcorpus\texecutions\texec_per_s\tresult\n' >"$history"
  fi
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' \
    "$(date -u -d "@${started[$t]}" +%FT%TZ)" "$(date -u +%FT%TZ)" "$t" \
    "$built_commit" \
    "$(sed -n 's/^INFO: Seed: //p' "$log" | head -1)" "$(basename "$(dirname "$work")")" \
    "${execs:-?}" "${rate:-?}" "${result%% *}" >>"$history"
  if [ "$result" = interrupted ]; then break; fi  # the user stopped the run
done
echo "== summary"
printf '%s\n' "${summary[@]}"

# What a failed target found. The log also holds the reports of the .mat reader processes
# (contained failures, not findings): the target's own report is the last one in the log.
for t in "${failures[@]}"; do
  log="$build/fuzz-$t.log"
  alloc_mb=2048 may_null=""
  if [ "$t" = matfile ]; then alloc_mb=640 may_null=":allocator_may_return_null=1"; fi
  artifacts="$build/fuzz-artifacts/$t"
  echo "== $t: the finding ($(sed -n 's/^INFO: Seed: //p' "$log" | head -1 | sed 's/^/seed /'))"
  # From a few lines before the last report's ERROR line (an uncaught exception's "terminate
  # called" and "what()" come just before libFuzzer's "deadly signal"): the report's key lines,
  # the top of the stack and libFuzzer's lines about the input.
  last=$( (grep -nE 'ERROR|runtime error:' "$log" | tail -1 | cut -d: -f1) || true)
  { tail -n +$((${last:-1} > 8 ? ${last:-1} - 8 : 1)) "$log" |
    grep -E 'ERROR|runtime error:|terminate called|what\(\)|SUMMARY|^MS:|Test unit written|^ +#[0-4] ' |
    head -n 16 | cut -c1-300; } || true
  input=$( (find "$artifacts" -type f -newermt "@${started[$t]}" -printf '%T@ %p\n' 2>/dev/null |
    sort -n | tail -1 | cut -d' ' -f2-) || true)
  if [ -n "$input" ] && [ "$t" = matfile -o "$t" = campaign -o "$t" = test_yaml ]; then
    # The run was unsymbolized or without allocation stacks (above): the input once more, for
    # the full report with file and line.
    echo "$t: the input replayed with a full report (log $log.replay):"
    ASAN_OPTIONS="max_allocation_size_mb=$alloc_mb$may_null:symbolize=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}" \
      LSAN_OPTIONS="suppressions=$root/fuzz/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}" \
      "$build/fuzz/${t}_fuzz" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=1048576 \
      "$input" >"$log.replay" 2>&1 || true
    last=$( (grep -nE 'ERROR|runtime error:' "$log.replay" | tail -1 | cut -d: -f1) || true)
    { tail -n +$((${last:-1} > 8 ? ${last:-1} - 8 : 1)) "$log.replay" |
      grep -E 'ERROR|runtime error:|terminate called|what\(\)|SUMMARY|^ +#[0-9] ' |
      head -n 16 | cut -c1-300; } || true
  fi
  if [ -n "$input" ] && [ "$(stat -c %s "$input")" -le 65536 ]; then
    echo "$t input $(basename "$input"), base64 (decode with base64 -d):"
    base64 -w0 "$input"
    echo
  fi
done
exit $status
