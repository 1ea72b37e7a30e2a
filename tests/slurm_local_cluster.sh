#!/usr/bin/env bash
# A throw-away single-node Slurm cluster on localhost, for tests/test_study_slurm.cpp.
#
#   slurm_local_cluster.sh start DIR   writes DIR/slurm.conf, starts munged, slurmctld and slurmd
#                                      with every file (keys, sockets, state, spool, logs, pids)
#                                      under DIR, waits until the node is idle. Exit 0 when the
#                                      cluster is up; exit 77 with the reason on stderr when it
#                                      cannot be brought up here (packages missing, a daemon
#                                      refused to start); DIR/env then holds SLURM_CONF=...
#   slurm_local_cluster.sh stop DIR    stops the daemons that `start` started (by their pid files).
#
# No cgroups: ProctrackType=proctrack/linuxproc, TaskPlugin=task/none, so it runs in a plain
# container as root (the CI machine). Ports are picked from the pid so two checkouts do not clash.
set -uo pipefail

cmd=${1:-}
dir=${2:-}
if [ -z "$cmd" ] || [ -z "$dir" ]; then
  echo "usage: $0 start|stop DIR" >&2
  exit 2
fi

skip() {
  echo "slurm_local_cluster: $*" >&2
  for log in munged.log slurmctld.log slurmd.log; do
    if [ -s "$dir/$log" ]; then
      echo "--- last lines of $dir/$log:" >&2
      tail -n 5 "$dir/$log" >&2
    fi
  done
  stop_daemons
  exit 77
}

# TERM to all three at once (each takes ~2 s to shut down), then KILL what is left after 5 s.
stop_daemons() {
  local pids=()
  for name in slurmd slurmctld munged; do
    local pidfile="$dir/$name.pid"
    if [ -s "$pidfile" ]; then
      pids+=("$(cat "$pidfile")")
      kill "${pids[-1]}" 2>/dev/null
      rm -f "$pidfile"
    fi
  done
  for pid in "${pids[@]}"; do
    for _ in $(seq 1 50); do
      kill -0 "$pid" 2>/dev/null || break
      sleep 0.1
    done
    kill -9 "$pid" 2>/dev/null
  done
}

if [ "$cmd" = stop ]; then
  stop_daemons
  exit 0
fi
[ "$cmd" = start ] || { echo "usage: $0 start|stop DIR" >&2; exit 2; }

for tool in munged mungekey slurmctld slurmd sbatch squeue sinfo scontrol; do
  command -v "$tool" >/dev/null 2>&1 || PATH="$PATH:/usr/sbin"
  command -v "$tool" >/dev/null 2>&1 ||
    { echo "slurm_local_cluster: $tool not found (scripts/install-deps.sh installs slurm-wlm and munge)" >&2; exit 77; }
done
[ "$(id -u)" -eq 0 ] || { echo "slurm_local_cluster: needs root (slurmd starts jobs as their user)" >&2; exit 77; }

mkdir -p "$dir/state" "$dir/spool" "$dir/munge"
chmod 700 "$dir/munge"
host=localhost
cpus=$(nproc)
base=$(( 20000 + ($$ % 2000) * 2 ))

# munge: own key, socket and state; --force because the directories are not the packaged ones.
mungekey --create --keyfile="$dir/munge/munge.key" --force >/dev/null 2>&1 ||
  dd if=/dev/urandom of="$dir/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$dir/munge/munge.key"
munged --force --key-file="$dir/munge/munge.key" --socket="$dir/munge/munge.socket" \
  --pid-file="$dir/munged.pid" --log-file="$dir/munged.log" --seed-file="$dir/munge/munge.seed" ||
  skip "munged did not start"

cat >"$dir/slurm.conf" <<EOF
ClusterName=bivotest
SlurmctldHost=$host
SlurmctldPort=$base
SlurmdPort=$(( base + 1 ))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge/munge.socket
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool/%n
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
SwitchType=switch/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/builtin
# Pending jobs (the merge, once its dependency is met) are looked at every second, not 60.
SchedulerParameters=sched_interval=1
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
ReturnToService=2
SlurmdTimeout=30
InactiveLimit=0
KillWait=5
MinJobAge=300
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
echo "SLURM_CONF=$dir/slurm.conf" >"$dir/env"
export SLURM_CONF="$dir/slurm.conf"

slurmctld -i >/dev/null 2>&1 || skip "slurmctld did not start"
slurmd -N "$host" >/dev/null 2>&1 || skip "slurmd did not start"

for _ in $(seq 1 60); do
  state=$(sinfo -h -N -o %t 2>/dev/null | head -n 1)
  case "$state" in
    idle*|mix*|alloc*) echo "slurm_local_cluster: up (node $host, $cpus CPUs, port $base)"; exit 0 ;;
  esac
  sleep 0.5
done
skip "the node did not become idle within 30 s (state '${state:-none}')"
