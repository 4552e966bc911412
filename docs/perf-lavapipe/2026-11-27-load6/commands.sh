# load6 engineer, 2026-11-27 18:25-18:26 UTC, this machine (shared 2-core AMD EPYC, lavapipe), from the load6
# worktree at 0427001 (REPO: main's checkout, whose working tree held main at 62c1110, load5 merged):
export XDG_RUNTIME_DIR=/tmp LP_NUM_THREADS=1
for r in 1 2; do order="load6 main"; [ $r = 2 ] && order="main load6"
  for m in cold warm; do for t in $order; do tree=.; [ $t = main ] && tree=REPO
    PYTHONPATH=$tree python benchmarks/load_compare.py $t 10000 load_compare.csv $m \
      $([ $r = 1 ] && echo --split=load_split.csv); done; done; done
