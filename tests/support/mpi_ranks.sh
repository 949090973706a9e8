#!/usr/bin/env bash
# The hierarchical solve on 1, 2 and 3 ranks (more ranks than cores: --oversubscribe) must write
# byte for byte the patches of one process without mpirun.
#   mpi_ranks.sh MPIEXEC RADIOSITY SCENE [OPTIONS...]
set -euo pipefail
mpiexec=$1 radiosity=$2 scene=$3
shift 3
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
solve=(--solver hierarchical --quiet "$@")
"$radiosity" "$scene" "${solve[@]}" --dump-patches "$dir/alone.csv" 2>/dev/null
for n in 1 2 3; do
  "$mpiexec" --oversubscribe -np "$n" "$radiosity" "$scene" "${solve[@]}" \
    --dump-patches "$dir/ranks$n.csv" 2>"$dir/log$n"
  cmp "$dir/alone.csv" "$dir/ranks$n.csv" || { cat "$dir/log$n"; exit 1; }
  echo "$n rank(s): the same $(wc -l <"$dir/alone.csv") lines; $(tail -n 1 "$dir/log$n")"
done
