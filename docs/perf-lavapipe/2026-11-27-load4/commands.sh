#!/bin/sh
# lavapipe rounds of issue 31.3's load, fourth pass (load4 engineer), from the load4 worktree; MAIN: main's checkout.
# Two rounds, each tree cold (empty parse cache) then warm, alternating trees; then the workers' probe of each tree.
set -u
D=docs/perf-lavapipe/2026-11-27-load4
export XDG_RUNTIME_DIR=/tmp LP_NUM_THREADS=1
PY=${PY:-python}
for round in 1 2; do
  for tree in load4 main; do
    if [ "$tree" = main ]; then P=$MAIN; else P=$PWD; fi
    for mode in cold warm; do
      echo "== round $round $tree $mode $(date -u +%H:%M:%S)"
      PYTHONPATH=$P $PY benchmarks/load_compare.py $tree 10000 $D/load_compare.csv $mode --split=$D/load_split.csv \
        | tail -1
    done
  done
done
for tree in load4 main; do
  if [ "$tree" = main ]; then P=$MAIN; else P=$PWD; fi
  echo "== probe $tree $(date -u +%H:%M:%S)"
  PYTHONPATH=$P $PY benchmarks/worker_cold_probe.py $tree 10000 2 $D/worker_probe.csv | tail -4
done
