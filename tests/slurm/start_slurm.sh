#!/usr/bin/env bash
# Starts a private single-node Slurm (munged + slurmctld + slurmd) in DIR, for tests.
#
#   tests/slurm/start_slurm.sh DIR      -> prints "export SLURM_CONF=DIR/slurm.conf" on success
#   tests/slurm/stop_slurm.sh DIR       -> stops exactly the processes this script started
#
# No systemd here: each daemon runs in the foreground flag (-F / -D), backgrounded by this
# script, logs in DIR; their process ids go to DIR/pids (one a line), which stop_slurm.sh
# kills and nothing else. Facts this relies on:
# - munged refuses a socket in a folder that is not world-readable-and-executable (0700 from
#   mktemp), so DIR is made 0755 and every parent must be world-executable (/tmp is).
# - Slurm clients (sbatch, squeue) find this cluster only through SLURM_CONF.
# - The node line copies the CPU layout from `slurmd -C`.
# - SchedulerParameters=batch_sched_delay=0 avoids a 3 s wait per scheduling round.
# - Accounting is off (no slurmdbd): sacct does not work; poll squeue.
# Exit status: 0 started, 3 packages missing (slurmctld, slurmd, munged), 1 failed to start
# (the logs in DIR say why).
set -u
DIR=${1:?usage: start_slurm.sh DIR}
for exe in munged mungekey slurmctld slurmd sbatch squeue; do
  command -v "$exe" >/dev/null 2>&1 || { echo "start_slurm: $exe not installed (apt-get install slurm-wlm munge)" >&2; exit 3; }
done
mkdir -p "$DIR"
DIR=$(cd "$DIR" && pwd)
chmod 755 "$DIR"
mkdir -p "$DIR/munge" "$DIR/state" "$DIR/spool"
chmod 755 "$DIR/munge"
: > "$DIR/pids"

# munge: a key of our own, a socket in DIR.
dd if=/dev/urandom of="$DIR/munge/munge.key" bs=1024 count=1 status=none
chmod 600 "$DIR/munge/munge.key"
SOCK="$DIR/munge/munge.socket"
munged -F --force --socket="$SOCK" --key-file="$DIR/munge/munge.key" --pid-file="$DIR/munge/munged.pid" \
  --log-file="$DIR/munge/munged.log" --seed-file="$DIR/munge/munged.seed" >"$DIR/munge/munged.out" 2>&1 &
echo $! >> "$DIR/pids"
for _ in $(seq 50); do [ -S "$SOCK" ] && break; sleep 0.1; done
[ -S "$SOCK" ] || { echo "start_slurm: munged did not start (see $DIR/munge/munged.log)" >&2; exit 1; }

# Ports away from the defaults (6817/6818), in case a real Slurm or another test runs here.
BASE=$(( 20000 + (RANDOM % 20000) ))
HOST=$(hostname -s)
NODE=$(slurmd -C | head -1 | sed -e "s/^NodeName=[^ ]*/NodeName=$HOST/")
cat > "$DIR/slurm.conf" <<CONF
ClusterName=millwear-test
SlurmctldHost=$HOST
SlurmUser=root
SlurmdUser=root
SlurmctldPort=$BASE
SlurmdPort=$((BASE + 1))
AuthType=auth/munge
AuthInfo=socket=$SOCK
CredType=cred/munge
StateSaveLocation=$DIR/state
SlurmdSpoolDir=$DIR/spool
SlurmctldPidFile=$DIR/slurmctld.pid
SlurmdPidFile=$DIR/slurmd.pid
SlurmctldLogFile=$DIR/slurmctld.log
SlurmdLogFile=$DIR/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
SchedulerType=sched/backfill
SchedulerParameters=batch_sched_delay=0
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
ReturnToService=2
MaxArraySize=10001
$NODE State=UNKNOWN
PartitionName=screen Nodes=$HOST Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$DIR/slurm.conf"
slurmctld -D -i -f "$SLURM_CONF" >"$DIR/slurmctld.out" 2>&1 &
echo $! >> "$DIR/pids"
slurmd -D -f "$SLURM_CONF" >"$DIR/slurmd.out" 2>&1 &
echo $! >> "$DIR/pids"
# Ready when the node is idle.
for _ in $(seq 100); do
  state=$(sinfo -h -N -o "%t" 2>/dev/null | head -1)
  [ "$state" = "idle" ] && { echo "export SLURM_CONF=$SLURM_CONF"; exit 0; }
  sleep 0.1
done
echo "start_slurm: the node did not come up (state '${state:-none}'; see $DIR/slurmctld.log, $DIR/slurmd.log)" >&2
exit 1
