#!/usr/bin/env bash
# Runs every (system, kryst configuration) pair of src/main.rs in its own process, each under
# a wall-clock limit (LIMIT_S, default 120 s) and an address-space limit (ulimit -v, default
# 8 GB), so that a configuration that hangs or exhausts memory is recorded instead of
# stopping the run. Results: data/kryst_results.csv (one row per pair) and stdout.
set -u
cd "$(dirname "$0")"
LIMIT_S=${LIMIT_S:-120}
VMEM_KB=${VMEM_KB:-8000000}
cargo build --release -q || exit 1
rm -f data/kryst_results.csv
M="jacobi amg-default sa sa-mis2"
E="jacobi amg-default sa sa-nodal sa-nodal-rbm sa-nodal-rbm-mis2"
for sys in membrane63 membrane127 membrane255 elastic32 elastic64 elastic128; do
  case $sys in membrane*) cfgs=$M ;; *) cfgs=$E ;; esac
  for cfg in $cfgs; do
    ( ulimit -v "$VMEM_KB"; timeout "$LIMIT_S" ./target/release/amg_eval "$sys" "$cfg" ) \
      > /tmp/amg_eval_one.log 2>&1
    rc=$?
    grep -E "^$sys " /tmp/amg_eval_one.log
    if [ $rc -ne 0 ]; then
      case $rc in
        124) why="timeout > ${LIMIT_S} s" ;;
        134) why="abort: $(grep -m1 -o 'memory allocation of [0-9]* bytes failed' /tmp/amg_eval_one.log || echo 'SIGABRT')" ;;
        *) why="exit $rc" ;;
      esac
      echo "$sys $cfg FAILED: $why"
      echo "$sys,,$cfg,,FAILED: $why,,,," >> data/kryst_results.csv
    fi
  done
done
