# load5 engineer, 2026-11-27 17:51-17:52 UTC, this machine (shared 2-core AMD EPYC, lavapipe), from the load5
# worktree at 353eff0 (REPO: main's checkout, whose working tree held main after load4's merge):
export XDG_RUNTIME_DIR=/tmp LP_NUM_THREADS=1
for r in 1 2; do for t in load5 main; do tree=.; [ $t = main ] && tree=REPO
  for m in cold warm; do PYTHONPATH=$tree python benchmarks/load_compare.py $t 10000 load_compare.csv $m \
    $([ $r = 1 ] && echo --split=load_split.csv); done; done; done > log.txt
