#!/usr/bin/env bash
# run.sh BUILD TARGET CARD SECONDS [JOBS] - one libFuzzer campaign (make fuzz).
# Starts from the seeds in tests/fuzz/corpus/TARGET and the work corpus of
# earlier runs; prints one summary line: executions, coverage, corpus, crashes.
set -uo pipefail
build=$1 t=$2 c=$3 secs=$4 jobs=${5:-1}
# CARD "all": a target on the emulator (fuzz-TARGET, the card in the input);
# what the emulator prints (script errors, events) is not kept
name=$t-$c
[ "$c" = all ] && name=$t
bin=$build/fuzz/fuzz-$name
work=$build/fuzz/work/$name
log=$build/fuzz/log-$name.txt
mkdir -p "$work"
# an input's time limit: 10 s, on the emulator 60 s (an execution there runs
# up to 700 ms of emulated time under ASan and coverage, about 1 s alone,
# several on a loaded machine)
limit=10
[ "$c" = all ] && limit=60
args=(-max_total_time="$secs" -max_len=4096 -timeout="$limit" -rss_limit_mb=4096 -print_final_stats=1
      -artifact_prefix="$build/fuzz/crash-$name-")
[ "$c" = all ] && args+=(-close_fd_mask=3)
if [ "$jobs" -gt 1 ]; then
    args+=(-fork="$jobs" -ignore_crashes=1)
fi
"$bin" "${args[@]}" "$work" "tests/fuzz/corpus/$t" >"$log" 2>&1
rc=$?
execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | awk '{s+=$2} END {print s+0}')
last=$(grep -E '^#[0-9]+' "$log" | tail -1)
cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$last")
ft=$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<<"$last")
corp=$(sed -n 's/.* corp: \([0-9]*\/[0-9a-zA-Z]*\).*/\1/p' <<<"$last")
crashes=$(ls "$build/fuzz/" | grep -c "^crash-$name-" || true)
printf '%-7s %-4s %5ss  execs %-10s cov %-6s ft %-7s corpus %-12s crashes %s%s\n' \
    "$t" "$c" "$secs" "${execs:-?}" "${cov:-?}" "${ft:-?}" "${corp:-?}" "$crashes" \
    "$([ $rc -ne 0 ] && echo "  (exit $rc, see $log)")"
exit 0
