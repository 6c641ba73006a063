#!/usr/bin/env bash
# A one-node Slurm cluster on this machine, for tests: munge, slurmctld and slurmd from Debian's
# packages (slurm-wlm), run as root from a private directory with their own key, sockets, ports,
# state and logs, so nothing of the machine's own configuration is read or changed.
# Source it, then:   slurm_start DIR   (exports SLURM_CONF; returns when the node is idle)
#                    slurm_stop        (also run on exit)
# Needs root (slurmd runs jobs as their submitting user).

slurm_free_port() {  # a TCP port nothing listens on
  python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1]); s.close()'
}

slurm_start() {
  local dir=$1 cpus
  cpus=$(nproc)
  mkdir -p "$dir"/{state,spool,munge}
  chmod 700 "$dir/munge"
  # munged insists on a key only its user can read and on directories others cannot write.
  dd if=/dev/urandom of="$dir/munge/munge.key" bs=1024 count=1 status=none
  chmod 400 "$dir/munge/munge.key"
  munged --force --key-file="$dir/munge/munge.key" --socket="$dir/munge/munge.socket" \
    --pid-file="$dir/munge/munged.pid" --log-file="$dir/munge/munged.log" --seed-file="$dir/munge/munged.seed" ||
    { echo "one_node_slurm: munged did not start:"; cat "$dir/munge/munged.log"; return 1; }
  SLURM_TEST_DIR=$dir
  cat > "$dir/slurm.conf" <<CONF
ClusterName=uavtest
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$(slurm_free_port)
SlurmdPort=$(slurm_free_port)
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge/munge.socket
SlurmUser=root
SlurmdUser=root
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
SwitchType=switch/none
MpiDefault=none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
NodeName=localhost NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=bench Nodes=localhost Default=YES MaxTime=INFINITE State=UP
CONF
  export SLURM_CONF=$dir/slurm.conf
  slurmctld -f "$SLURM_CONF" -i || { echo "one_node_slurm: slurmctld did not start:"; tail -20 "$dir/slurmctld.log"; return 1; }
  slurmd -f "$SLURM_CONF" -N localhost || { echo "one_node_slurm: slurmd did not start:"; tail -20 "$dir/slurmd.log"; return 1; }
  trap slurm_stop EXIT
  local i
  for i in $(seq 1 60); do
    sinfo -h -N -o '%T' 2> /dev/null | grep -q '^idle' && return 0
    sleep 0.5
  done
  echo "one_node_slurm: the node never came up idle:"
  sinfo -N 2>&1; tail -20 "$dir/slurmctld.log" "$dir/slurmd.log"
  return 1
}

slurm_stop() {
  local dir=${SLURM_TEST_DIR:-}
  [ -n "$dir" ] || return 0
  local f
  for f in slurmd slurmctld munge/munged; do
    [ -f "$dir/$f.pid" ] && kill "$(cat "$dir/$f.pid")" 2> /dev/null
  done
  SLURM_TEST_DIR=
}
