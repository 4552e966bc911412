# Three alternating rounds, each tree warm then cold (BRANCH: this branch's checkout at dec14bc,
# MAIN: main's checkout at 85d48bf, VENV: the shared virtual environment, OUT: this folder), 2026-11-27 15:57-16:01 UTC
cd BRANCH
export XDG_RUNTIME_DIR=/tmp LP_NUM_THREADS=1
for r in 1 2 3; do
 for t in main load3; do
  if [ $t = main ]; then P=MAIN; else P=BRANCH; fi
  for m in warm cold; do
   PYTHONPATH=$P VENV/bin/python benchmarks/load_compare.py $t 10000 OUT/load_compare.csv $m --split=OUT/load_split.csv >> OUT/runs.log 2>&1
  done
 done
done
