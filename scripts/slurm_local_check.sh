#!/usr/bin/env bash
# Checks scripts/slurm_array.sh on a real single-node Slurm (Debian's slurm-wlm + munge,
# installed if missing, configured here as one node with every core of this machine):
# an array of 4 shards of the scene-folder benchmark → `sweep merge` → rows identical (all
# columns but seconds*) to one unsharded run. Needs root; not part of CI. Usage:
#   bash scripts/slurm_local_check.sh [OUT]        (default results/slurm_check)
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
OUT=$(realpath -m "${1:-results/slurm_check}")
command -v slurmctld >/dev/null || apt-get install -y slurm-wlm munge
cargo build --release --bin sweep
SWEEP=$ROOT/target/release/sweep

# munge: a key and a running daemon.
if [ ! -s /etc/munge/munge.key ]; then
    mkdir -p /etc/munge
    dd if=/dev/urandom of=/etc/munge/munge.key bs=1024 count=1 status=none
fi
chown munge:munge /etc/munge/munge.key && chmod 400 /etc/munge/munge.key
mkdir -p /run/munge && chown munge:munge /run/munge
pgrep -x munged >/dev/null || runuser -u munge -- /usr/sbin/munged

# slurm: one node, one partition, no accounting, no cgroups.
HOST=$(hostname -s)
mkdir -p /etc/slurm /var/spool/slurmctld /var/spool/slurmd /var/log/slurm
cat > /etc/slurm/slurm.conf <<CONF
ClusterName=penaltylab
SlurmctldHost=$HOST
SlurmUser=root
AuthType=auth/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
ReturnToService=2
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
StateSaveLocation=/var/spool/slurmctld
SlurmdSpoolDir=/var/spool/slurmd
SlurmctldPidFile=/run/slurmctld.pid
SlurmdPidFile=/run/slurmd.pid
SlurmctldLogFile=/var/log/slurm/slurmctld.log
SlurmdLogFile=/var/log/slurm/slurmd.log
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
NodeName=$HOST CPUs=$(nproc) State=UNKNOWN
PartitionName=main Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
pgrep -x slurmctld >/dev/null || slurmctld -c
pgrep -x slurmd >/dev/null || slurmd
for _ in $(seq 30); do sinfo -h -o %t 2>/dev/null | grep -q idle && break; sleep 1; done
sinfo

# The run: the folder benchmark's scenes, 4 shards as a job array, then one unsharded run.
rm -rf "$OUT" && mkdir -p "$OUT"
"$SWEEP" --config scripts/folder.toml --metrics none --no-figures --quiet \
    --out "$OUT/gen" --write-scenes "$OUT/scenes" --dense-scenes
FLAGS=(--config "$ROOT/scripts/folder.toml" --scenes-dir "$OUT/scenes")
sbatch --wait --array=1-4 --cpus-per-task=1 --chdir="$OUT" \
    scripts/slurm_array.sh "$OUT/array" "${FLAGS[@]}"
"$SWEEP" merge "$OUT/merged" "$OUT"/array/shard-*
"$SWEEP" "${FLAGS[@]}" --no-figures --quiet --out "$OUT/single"

python3 - "$OUT/merged/rows.csv" "$OUT/single/rows.csv" <<'PY'
import csv, sys
def rows(p):
    out = []
    for r in csv.DictReader(open(p)):
        out.append({k: v for k, v in r.items() if not k.startswith("seconds")})
    return out
a, b = rows(sys.argv[1]), rows(sys.argv[2])
assert len(a) == len(b) and a == b, "merged shards differ from the unsharded run"
print(f"OK: {len(a)} rows from 4 Slurm array tasks, merged, identical to the unsharded run "
      "(all columns but seconds*)")
PY
