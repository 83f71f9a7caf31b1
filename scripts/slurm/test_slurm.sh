#!/bin/bash
# Proves the Slurm path on a real (single-node, localhost) Slurm: starts munged, slurmctld and
# slurmd directly (no systemd) from Debian's slurm-wlm and munge with a minimal slurm.conf
# (proctrack/pgid, task/none, no accounting), submits a small sweep as a job array with
# `sbatch -W`, merges, runs the same sweep locally and checks the numbers are identical.
# Run by `make test-slurm` (installs its packages itself). Needs root (or sudo) to install
# packages and run munged as the munge user. Everything else lives in a temporary folder and
# is stopped on exit. docs/sweeps.md "Slurm".
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
FOVSIM=${FOVSIM:-$ROOT/build/fovsim}
CONFIG=${CONFIG:-$ROOT/scripts/slurm/test_sweep.json}
SHARDS=${SHARDS:-3}
SUDO=""; AS_MUNGE="runuser -u munge --"
[ "$(id -u)" = 0 ] || { SUDO=sudo; AS_MUNGE="sudo -u munge"; }

[ -x "$FOVSIM" ] || { echo "test_slurm: $FOVSIM not built (make build)" >&2; exit 2; }
need=""
for p in slurm-wlm munge; do dpkg-query -W -f='${Status}' $p 2>/dev/null | grep -q "ok installed" || need="$need $p"; done
if [ -n "$need" ]; then
  echo "test_slurm: installing$need"
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends $need
fi

WORK=$(mktemp -d /tmp/fovsim-slurm.XXXXXX)
chmod 755 "$WORK"
PIDS=()
cleanup() {
  for p in "${PIDS[@]:-}"; do [ -n "$p" ] && $SUDO kill "$p" 2>/dev/null || true; done
  sleep 1
  [ -n "${MUNGE_PID:-}" ] && $SUDO kill "$MUNGE_PID" 2>/dev/null || true
  [ "${KEEP:-0}" = 1 ] || rm -rf "$WORK"
}
trap cleanup EXIT

# ---- munge: own key, socket and pid file in $WORK, run as the munge user ----
M=$WORK/munge
$SUDO mkdir -p "$M"
$SUDO dd if=/dev/urandom of="$M/munge.key" bs=1 count=1024 status=none
$SUDO chown -R munge:munge "$M"
$SUDO chmod 755 "$M"
$SUDO chmod 400 "$M/munge.key"
$AS_MUNGE /usr/sbin/munged --key-file="$M/munge.key" --socket="$M/munge.socket" \
  --pid-file="$M/munged.pid" --log-file="$M/munged.log" --seed-file="$M/munged.seed"
sleep 0.5
MUNGE_PID=$($SUDO cat "$M/munged.pid")
$SUDO chmod 755 "$M"

# ---- minimal single-node slurm.conf ----
HOST=$(hostname -s)
CPUS=$(nproc)
MEM=$(( $(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 / 2 ))
mkdir -p "$WORK/state" "$WORK/spool" "$WORK/log"
cat > "$WORK/slurm.conf" <<EOF
ClusterName=fovsimtest
SlurmctldHost=$HOST
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$M/munge.socket
CredType=cred/munge
ProctrackType=proctrack/pgid
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
ReturnToService=2
SlurmctldPort=${SLURMCTLD_PORT:-16817}
SlurmdPort=${SLURMD_PORT:-16818}
StateSaveLocation=$WORK/state
SlurmdSpoolDir=$WORK/spool
SlurmctldPidFile=$WORK/slurmctld.pid
SlurmdPidFile=$WORK/slurmd.pid
SlurmctldLogFile=$WORK/log/slurmctld.log
SlurmdLogFile=$WORK/log/slurmd.log
NodeName=$HOST CPUs=$CPUS RealMemory=$MEM State=UNKNOWN
PartitionName=test Nodes=$HOST Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF=$WORK/slurm.conf

$SUDO env SLURM_CONF="$SLURM_CONF" /usr/sbin/slurmctld -D -c -f "$SLURM_CONF" > "$WORK/log/slurmctld.out" 2>&1 &
PIDS+=($!)
sleep 1
$SUDO env SLURM_CONF="$SLURM_CONF" /usr/sbin/slurmd -D -c -f "$SLURM_CONF" > "$WORK/log/slurmd.out" 2>&1 &
PIDS+=($!)
for i in $(seq 1 60); do
  if sinfo -h -o %t 2>/dev/null | grep -Eq '^(idle|mix|alloc)'; then break; fi
  sleep 1
  if [ "$i" = 60 ]; then
    echo "test_slurm: the node did not come up; logs:" >&2
    tail -n 20 "$WORK"/log/* >&2
    exit 1
  fi
done
echo "test_slurm: single-node Slurm up on $HOST ($CPUS CPUs): $(sinfo -h -o '%P %t %D')"

# ---- the sweep as a job array, then merge ----
OUT=$WORK/array
LOCAL=$WORK/local
cd "$ROOT"
export FOVSIM
sbatch -W --array=0-$((SHARDS - 1)) --cpus-per-task=1 --output="$WORK/log/task-%a.out" \
  scripts/slurm/sweep.sbatch "$CONFIG" "$OUT"
for f in "$WORK"/log/task-*.out; do sed "s|^|  $(basename "$f"): |" "$f"; done
"$FOVSIM" merge "$OUT" --no-plots
"$FOVSIM" sweep "$CONFIG" --out "$LOCAL" --no-plots -q
/usr/bin/python3 scripts/slurm/compare_summaries.py "$OUT/summary.csv" "$LOCAL/summary.csv"
echo "test_slurm: PASS ($SHARDS array tasks merged == local run)"
