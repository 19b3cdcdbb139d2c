#!/usr/bin/env bash
# Runs the cluster walk-through of the README for real: a single-node Slurm (slurmctld + slurmd +
# munge, started here and stopped on exit) runs examples/cluster/reach_array.sbatch as a 4-task
# job array, `helixreach merge` joins the shards, and the merged rows must equal those of one
# unsharded `reach` run. Needs root (CI runs as root) and Debian's slurm packages, which it
# installs when missing. Usage: .ci/slurm_cluster.sh PATH/TO/helixreach
set -euo pipefail
bin=$(readlink -f "${1:?usage: $0 PATH/TO/helixreach}")
repo=$(cd "$(dirname "$0")/.." && pwd)
if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq slurmctld slurmd slurm-client munge >/dev/null
fi
work=$(mktemp -d)
host=$(hostname -s)
cleanup() {
    [ -f "$work/slurmd.pid" ] && kill "$(cat "$work/slurmd.pid")" 2>/dev/null || true
    [ -f "$work/slurmctld.pid" ] && kill "$(cat "$work/slurmctld.pid")" 2>/dev/null || true
    [ -f "$work/munged.pid" ] && kill "$(cat "$work/munged.pid")" 2>/dev/null || true
    sleep 1
    rm -rf "$work"
}
trap cleanup EXIT

# munge: a fresh key in the work directory, its own socket (no system service is touched).
mkdir -p "$work/munge"
dd if=/dev/urandom of="$work/munge/munge.key" bs=1024 count=1 status=none
chmod 700 "$work/munge"; chmod 400 "$work/munge/munge.key"
munged --force --key-file="$work/munge/munge.key" --socket="$work/munge/socket" \
    --pid-file="$work/munged.pid" --log-file="$work/munge/log" --seed-file="$work/munge/seed"

# slurm: one node, one partition, no cgroups (proctrack/linuxproc, task/none).
mkdir -p "$work/state" "$work/spool"
cpus=$(nproc)
cat > "$work/slurm.conf" <<CONF
ClusterName=helixreach-ci
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$work/munge/socket
CredType=cred/munge
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
SlurmctldPort=16817
SlurmdPort=16818
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MpiDefault=none
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
NodeName=$host CPUs=$cpus State=UNKNOWN
PartitionName=ci Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$work/slurm.conf
slurmctld
slurmd
for _ in $(seq 60); do
    sinfo -h -o %T 2>/dev/null | grep -Eq '^(idle|mixed|allocated)' && break
    sleep 1
done
sinfo -h -o '%P %T %c' >&2

# The walk-through: a 4-task array, then merge.
mkdir -p "$work/run"
cd "$work/run"
HELIXREACH="$bin" DIRECTIONS=40 OUT_DIR="$work/run" \
    sbatch --array=0-3 --wait --export=ALL "$repo/examples/cluster/reach_array.sbatch" >&2
"$bin" merge --out reach.csv reach_shard_0.csv reach_shard_1.csv reach_shard_2.csv reach_shard_3.csv
"$bin" reach --rig sawyer-seed --fibonacci 40 --quarter --threads 1 --quiet --out single.csv
# Plain CSV (the settings records are the sidecars): the merged sweep equals the unsharded one.
if ! diff reach.csv single.csv >&2; then
    echo "slurm: the merged shards differ from the unsharded run" >&2
    exit 1
fi
echo "slurm: 4-task job array merged, $(($(wc -l < reach.csv) - 1)) rows identical to the unsharded run" >&2
