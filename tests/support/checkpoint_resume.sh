#!/usr/bin/env bash
# A checkpointed hierarchical solve killed with SIGKILL mid-run, then resumed: the resumed run
# must write byte for byte the patches of an uninterrupted run.
#   checkpoint_resume.sh RADIOSITY SCENE                     one process, killed and resumed
#   checkpoint_resume.sh RADIOSITY SCENE MPIEXEC N M         N ranks, one rank killed (the job
#                                                            must end within seconds, naming
#                                                            it), resumed on M ranks
set -euo pipefail
radiosity=$1 scene=$2 mpiexec=${3:-} ranks=${4:-1} resume_ranks=${5:-1}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
solve=(--solver hierarchical --quiet)
launch() {  # launch RANKS ARGS...: the program on RANKS ranks, or as one process
  local n=$1
  shift
  if [ -n "$mpiexec" ]; then "$mpiexec" --oversubscribe -np "$n" "$@"; else "$@"; fi
}

launch "$ranks" "$radiosity" "$scene" "${solve[@]}" --dump-patches "$dir/whole.csv" 2>/dev/null

# Started here, not through launch: `launch ... &` would make $! a subshell, and killing that
# would leave the program itself running (and writing its outputs while the resumed run does).
checkpointed=("$radiosity" "$scene" "${solve[@]}" --dump-patches "$dir/cut.csv"
  --checkpoint "$dir/state" --checkpoint-every 0.2)
if [ -n "$mpiexec" ]; then
  "$mpiexec" --oversubscribe -np "$ranks" "${checkpointed[@]}" >"$dir/log" 2>&1 &
else
  "${checkpointed[@]}" >"$dir/log" 2>&1 &
fi
job=$!
for _ in $(seq 1 1200); do [ -s "$dir/state" ] && break; sleep 0.01; done
[ -s "$dir/state" ] || { echo "FAIL: no checkpoint was written"; exit 1; }
sleep 0.3  # into the solve, past the first checkpoint
victim=$job
if [ -n "$mpiexec" ]; then  # a rank, not mpirun: the processes that run the program itself
  victim=$(pgrep -f "^$radiosity $scene" | tail -n 1)
fi
kill -0 "$victim" 2>/dev/null || { echo "FAIL: the run ended before it could be killed"; exit 1; }
killed_at=$(date +%s%N)
kill -9 "$victim"
status=0
wait "$job" || status=$?
took_ms=$((($(date +%s%N) - killed_at) / 1000000))
echo "killed $victim; the job ended with status $status after ${took_ms} ms"
! kill -0 "$victim" 2>/dev/null || { echo "FAIL: process $victim outlived its kill -9"; exit 1; }
[ "$status" -ne 0 ] || { echo "FAIL: the killed job reported success"; exit 1; }
if [ -n "$mpiexec" ]; then
  grep -q "rank" "$dir/log" || { echo "FAIL: no message names the lost rank:"; cat "$dir/log"; exit 1; }
  ((took_ms < 10000)) || { echo "FAIL: the job took ${took_ms} ms to end"; exit 1; }
fi
[ ! -e "$dir/cut.csv" ] || { echo "FAIL: the killed run wrote its outputs"; exit 1; }

launch "$resume_ranks" "$radiosity" "$scene" "${solve[@]}" --dump-patches "$dir/cut.csv" \
  --resume "$dir/state" 2>/dev/null
cmp "$dir/whole.csv" "$dir/cut.csv"
echo "resumed on $resume_ranks rank(s): the same $(wc -l <"$dir/whole.csv") lines"
