#!/usr/bin/env bash
# A single-node Slurm cluster on this machine (slurmctld, slurmd and munge from Debian's slurm-wlm,
# installed by scripts/install-deps.sh): submits scripts/slurm/vdb_render.sbatch, the example batch
# script of docs/scaling.md, with 2 ranks on this node, and checks that the image is the one a
# single process renders, to the byte, and that both ranks took tiles.
# Usage: tests/slurm/slurm_test.sh BUILD_DIR SOURCE_DIR. Exit 77 (skipped) without root or Slurm.
set -euo pipefail
build=$(cd "$1" && pwd)
source=$(cd "$2" && pwd)
for program in slurmctld slurmd sbatch sinfo munged; do
  command -v "$program" >/dev/null || { echo "skipped: $program is not installed (scripts/install-deps.sh)"; exit 77; }
done
[[ $(id -u) -eq 0 ]] || { echo "skipped: slurmd runs as root"; exit 77; }

dir=$(mktemp -d /tmp/vdbappear-slurm.XXXXXX)
started_munged=""
# Stops a daemon by its pid file: TERM, then KILL if it is still there after 10 s.
stop() {
  [[ -f $1 ]] || return 0
  local pid
  pid=$(cat "$1")
  kill "$pid" 2>/dev/null || return 0
  for _ in $(seq 100); do
    kill -0 "$pid" 2>/dev/null || return 0
    sleep 0.1
  done
  kill -9 "$pid" 2>/dev/null || true
}
cleanup() {
  stop "$dir/slurmd.pid"
  stop "$dir/slurmctld.pid"
  [[ -n $started_munged ]] && stop /run/munge/munged.pid
  rm -rf "$dir"
}
trap cleanup EXIT

# munge authenticates Slurm's messages: its daemon runs as the user munge.
if [[ ! -S /run/munge/munge.socket.2 ]] || ! pgrep -x munged >/dev/null; then
  mkdir -p /run/munge && chown munge:munge /run/munge
  runuser -u munge -- /usr/sbin/munged --force
  started_munged=yes
  for _ in $(seq 50); do
    [[ -S /run/munge/munge.socket.2 ]] && break
    sleep 0.1
  done
fi

host=$(hostname)
port=$((20000 + RANDOM % 10000))
mkdir -p "$dir/state" "$dir/spool"
cat >"$dir/slurm.conf" <<EOF
ClusterName=vdbappear-test
SlurmctldHost=$host
SlurmUser=root
SlurmctldPort=$port
SlurmdPort=$((port + 1))
AuthType=auth/munge
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/pgid
TaskPlugin=task/none
SwitchType=switch/none
MpiDefault=none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
NodeName=$host CPUs=$(nproc) State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF=$dir/slurm.conf
slurmctld -f "$SLURM_CONF"
slurmd -f "$SLURM_CONF"
for _ in $(seq 60); do
  sinfo -h -o %T 2>/dev/null | grep -qx idle && break
  sleep 0.5
done
sinfo -h -o %T | grep -qx idle || { echo "FAIL: the node never became idle"; cat "$dir"/*.log; exit 1; }

medium=$dir/cloud.vdb
"$build/bin/vdb_make_medium" cloud --res 32 -o "$medium"
"$build/bin/vdb_render" "$medium" -o "$dir/solo.exr" --res 64x40 --spp 8 --seed 5 -j 1

# The example script as it is; sbatch's flags replace its cluster-sized #SBATCH lines.
sbatch --wait --nodes=1 --ntasks=2 --ntasks-per-node=2 --cpus-per-task=1 --mem=0 --time=10 \
  --output="$dir/job.log" \
  --export=ALL,VDB_RENDER="$build/bin/vdb_render",MEDIUM="$medium",OUT="$dir/slurm.exr",RES=64x40,SPP=8,SEED=5 \
  "$source/scripts/slurm/vdb_render.sbatch" || { echo "FAIL: the job failed"; cat "$dir/job.log"; exit 1; }

cmp "$dir/solo.exr" "$dir/slurm.exr" || { echo "FAIL: the Slurm job's image differs from one process's"; exit 1; }
python3 - "$dir/slurm.json" <<'EOF'
import json, sys
ranks = json.load(open(sys.argv[1]))["ranks"]
assert len(ranks) == 2 and all(r["paths"] > 0 for r in ranks), ranks
EOF
echo "the Slurm job's image (2 ranks, srun --mpi=pmix) is the single process's, to the byte"
