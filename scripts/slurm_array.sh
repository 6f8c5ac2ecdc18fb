#!/usr/bin/env bash
# One shard of a sweep per task of a Slurm job array; merge the shards afterwards.
#
#   sbatch --array=1-N --cpus-per-task=C scripts/slurm_array.sh OUT [sweep flags...]
#   # when every task has finished:
#   target/release/sweep merge OUT/merged OUT/shard-*
#
# Task K of N runs `sweep [flags] --shard K/N --threads C --out OUT/shard-K`, with --resume so
# that a requeued or preempted task continues where it stopped (nothing lost or duplicated).
# The shards are contiguous blocks of the scene order; `sweep merge` checks that they are one
# run (config, seed, commit, shard count, every shard once and complete) and writes rows.csv in
# scene order, identical to an unsharded run but for the seconds* columns.
# SWEEP overrides the binary (default: target/release/sweep under the submit directory).
#SBATCH --job-name=penalty-lab-sweep
#SBATCH --output=slurm-%A_%a.out
set -euo pipefail
OUT=${1:?usage: sbatch --array=1-N scripts/slurm_array.sh OUT [sweep flags...]}
shift
N=${SLURM_ARRAY_TASK_COUNT:?not running as a task of a Slurm job array}
K=${SLURM_ARRAY_TASK_ID:?not running as a task of a Slurm job array}
SWEEP=${SWEEP:-${SLURM_SUBMIT_DIR:-.}/target/release/sweep}
mkdir -p "$OUT"
exec "$SWEEP" "$@" --shard "$K/$N" --threads "${SLURM_CPUS_PER_TASK:-1}" \
    --no-figures --quiet --resume --out "$OUT/shard-$K"
