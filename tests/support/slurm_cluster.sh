#!/usr/bin/env bash
# A one-node Slurm cluster on loopback for the --slurm integration test (docs/testing.md#slurm):
# munged on its own socket and key, slurmctld and slurmd with their own configuration, ports,
# state and logs, all inside one folder. Nothing outside that folder is read or written, and
# nothing listens beyond 127.0.0.1.
#
#   slurm_cluster.sh start <dir>   starts the daemons; prints SLURM_CONF=<dir>/slurm.conf
#   slurm_cluster.sh stop <dir>    stops them (each by the pid file it wrote)
#
# Exit status 0 when the cluster answers (a node idle), else 1 with the reason on stderr (a
# missing program, a daemon that did not start: its log's last lines).
set -uo pipefail

cmd=${1:-}
dir=${2:-}
if [ -z "$cmd" ] || [ -z "$dir" ]; then
  echo "usage: slurm_cluster.sh start|stop <dir>" >&2
  exit 2
fi

stop() {
  for d in slurmd slurmctld munged; do
    if [ -f "$dir/$d.pid" ]; then
      kill "$(cat "$dir/$d.pid")" 2>/dev/null || true
    fi
  done
  # Wait for them to go, so the folder can be removed.
  for _ in $(seq 50); do
    alive=0
    for d in slurmd slurmctld munged; do
      if [ -f "$dir/$d.pid" ] && kill -0 "$(cat "$dir/$d.pid")" 2>/dev/null; then alive=1; fi
    done
    [ $alive -eq 0 ] && break
    sleep 0.1
  done
  # slurmd's job step daemons go with their jobs; kill any left over.
  for d in slurmd slurmctld munged; do
    if [ -f "$dir/$d.pid" ]; then kill -9 "$(cat "$dir/$d.pid")" 2>/dev/null || true; fi
  done
}

if [ "$cmd" = stop ]; then
  stop
  exit 0
fi
if [ "$cmd" != start ]; then
  echo "slurm_cluster.sh: unknown command $cmd" >&2
  exit 2
fi

for p in munged slurmctld slurmd sinfo sbatch; do
  if ! command -v "$p" >/dev/null 2>&1 && [ ! -x "/usr/sbin/$p" ]; then
    echo "slurm_cluster.sh: $p is not installed (Debian packages slurm-wlm and munge;" \
      "scripts/install-deps.sh installs them)" >&2
    exit 1
  fi
done
PATH="$PATH:/usr/sbin"

mkdir -p "$dir"
dir=$(cd "$dir" && pwd)
chmod 700 "$dir"
mkdir -p "$dir/state" "$dir/spool" "$dir/munge"
chmod 700 "$dir/munge"

# munge: a fresh key, its own socket.
dd if=/dev/urandom of="$dir/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$dir/munge/munge.key"
socket="$dir/munge/munge.socket"
if ! munged --force --socket="$socket" --key-file="$dir/munge/munge.key" \
  --pid-file="$dir/munged.pid" --log-file="$dir/munged.log" \
  --seed-file="$dir/munge/munged.seed" 2>"$dir/munged.err"; then
  echo "slurm_cluster.sh: munged did not start:" >&2
  tail -n 5 "$dir/munged.err" "$dir/munged.log" >&2 2>/dev/null
  stop
  exit 1
fi

# Two free ports on loopback.
read -r ctld_port slurmd_port < <(python3 - <<'EOF'
import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(*[x.getsockname()[1] for x in s])
EOF
)
user=$(id -un)
cpus=$(nproc)
mem=$(awk '/MemTotal/ {print int($2 / 1024 / 2)}' /proc/meminfo)
cat >"$dir/slurm.conf" <<EOF
ClusterName=chatterlab-test
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$socket
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
ReturnToService=2
SchedulerType=sched/builtin
SlurmctldParameters=enable_configless
MinJobAge=600
NodeName=localhost NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=test Nodes=localhost Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$dir/slurm.conf"

if ! slurmctld -f "$SLURM_CONF" 2>"$dir/slurmctld.err"; then
  echo "slurm_cluster.sh: slurmctld did not start:" >&2
  tail -n 5 "$dir/slurmctld.err" "$dir/slurmctld.log" >&2 2>/dev/null
  stop
  exit 1
fi
if ! slurmd -f "$SLURM_CONF" -N localhost 2>"$dir/slurmd.err"; then
  echo "slurm_cluster.sh: slurmd did not start:" >&2
  tail -n 5 "$dir/slurmd.err" "$dir/slurmd.log" >&2 2>/dev/null
  stop
  exit 1
fi

# Ready when the node is idle (up to 30 s).
for _ in $(seq 150); do
  state=$(sinfo -h -N -o %t 2>/dev/null | head -n 1)
  if [ "$state" = idle ]; then
    echo "SLURM_CONF=$SLURM_CONF"
    exit 0
  fi
  sleep 0.2
done
echo "slurm_cluster.sh: the node did not become idle in 30 s (state '${state:-none}'):" >&2
tail -n 5 "$dir/slurmctld.log" "$dir/slurmd.log" >&2 2>/dev/null
stop
exit 1
