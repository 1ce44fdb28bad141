#!/usr/bin/env bash
# A real one-node Slurm cluster on this machine (munged, slurmctld, slurmd
# on 127.0.0.1 with a generated slurm.conf), and conftrack's cluster
# workflow on it (docs/cluster.md):
#   1. `conftrack slurm` submits a 4-shard run of 16 events and the merge;
#      the merged report equals a single-process run of the same events
#      (summary.json physics and every histogram CSV).
#   2. One failing shard leaves the merge job unstarted
#      (DependencyNeverSatisfied); after the cause is removed, the resume
#      command (`conftrack slurm ... --resume`) re-runs only that shard and
#      the merge, which then equals the single-process run too.
# Every daemon started here is stopped (by its pid) on exit. Where the
# daemons cannot start, the test fails with their log: it never passes
# without having run.
#
# Usage: tests/slurm/slurm_cluster_test.sh path/to/conftrack
# Needs root (the daemons run as root, as in CI) and slurm-wlm + munge
# (scripts/install-deps.sh --slurm). Run by `make test-slurm` and .ci/run.
set -euo pipefail

conftrack=$(readlink -f "${1:?usage: $0 path/to/conftrack}")
timeout_s=${SLURM_TEST_TIMEOUT:-900}
here=$(cd "$(dirname "$0")" && pwd)

fail() {
  echo "slurm test: FAILED: $*" >&2
  exit 1
}

[ "$(id -u)" -eq 0 ] || fail "needs root to start munged, slurmctld and slurmd"
for tool in munged slurmctld slurmd sbatch squeue scontrol python3; do
  command -v "$tool" >/dev/null || fail "$tool not found (scripts/install-deps.sh --slurm)"
done

# The "shared file system": one folder that the daemons, the jobs and this
# script all see.
work=$(mktemp -d /tmp/conftrack-slurm.XXXXXX)
chmod 755 "$work"
mkdir -p "$work/munge" "$work/state" "$work/spool" "$work/log"
pids=()

stop_daemons() {
  # Daemons of this test only, by the pids they wrote.
  for pidfile in "$work/slurmd.pid" "$work/slurmctld.pid" "$work/munge/munged.pid"; do
    if [ -s "$pidfile" ]; then
      kill "$(cat "$pidfile")" 2>/dev/null || true
    fi
  done
  for pidfile in "$work/slurmd.pid" "$work/slurmctld.pid" "$work/munge/munged.pid"; do
    if [ -s "$pidfile" ]; then
      pid=$(cat "$pidfile")
      for _ in $(seq 50); do
        kill -0 "$pid" 2>/dev/null || break
        sleep 0.2
      done
      kill -9 "$pid" 2>/dev/null || true
    fi
  done
}
show_logs() {
  for f in "$work"/log/*.log; do
    [ -f "$f" ] && { echo "--- $f (last 20 lines)"; tail -n 20 "$f"; } >&2
  done
  for f in "$work"/study*/slurm/*.log; do
    [ -f "$f" ] && { echo "--- $f"; tail -n 5 "$f"; } >&2
  done
  return 0
}
on_exit() {
  status=$?
  [ $status -ne 0 ] && show_logs
  stop_daemons
  if [ $status -eq 0 ]; then
    rm -rf "$work"
  else
    echo "slurm test: files kept in $work" >&2
  fi
}
trap on_exit EXIT

# --- munge: a fresh key, a private socket
dd if=/dev/urandom of="$work/munge/munge.key" bs=1024 count=1 status=none
chmod 700 "$work/munge"
chmod 400 "$work/munge/munge.key"
munged -f --socket="$work/munge/munge.sock" --key-file="$work/munge/munge.key" \
  --log-file="$work/log/munged.log" --pid-file="$work/munge/munged.pid" \
  --seed-file="$work/munge/munged.seed" ||
  fail "munged did not start"

# --- slurm.conf: this host as the only node, on 127.0.0.1, free ports
node=$(uname -n)
node=${node%%.*}
read -r ctld_port slurmd_port < <(python3 -c '
import socket
socks = [socket.socket() for _ in range(2)]
for s in socks: s.bind(("127.0.0.1", 0))
print(*[s.getsockname()[1] for s in socks])')
cpus=$(nproc)
export SLURM_CONF="$work/slurm.conf"
cat >"$SLURM_CONF" <<EOF
ClusterName=conftrack-test
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
AuthType=auth/munge
AuthInfo=socket=$work/munge/munge.sock
CredType=cred/munge
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/log/slurmctld.log
SlurmdLogFile=$work/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
ReturnToService=2
MinJobAge=3600
NodeName=$node NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=test Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF

slurmctld -f "$SLURM_CONF" || fail "slurmctld did not start"
slurmd -f "$SLURM_CONF" -N "$node" || fail "slurmd did not start"
ready=0
for _ in $(seq 60); do
  if sinfo -h -o '%t' 2>/dev/null | grep -qE '^(idle|mix|alloc)'; then
    ready=1
    break
  fi
  sleep 1
done
[ $ready -eq 1 ] || fail "the node did not come up within 60 s (sinfo: $(sinfo -h 2>&1 | head -1))"
echo "slurm test: cluster up (node $node, $cpus CPUs, ports $ctld_port/$slurmd_port)"

deadline=$((SECONDS + timeout_s))

job_state() { scontrol show job "$1" 2>/dev/null | grep -oP 'JobState=\K\S+' | head -1; }
job_reason() { scontrol show job "$1" 2>/dev/null | grep -oP 'Reason=\K\S+' | head -1; }

# Waits until job $1 (all of its array tasks) left the queue.
wait_gone() {
  while squeue -h -j "$1" 2>/dev/null | grep -q .; do
    [ $SECONDS -lt $deadline ] || fail "job $1 still queued after ${timeout_s} s"
    sleep 2
  done
}

# Job ids from conftrack slurm's output ("shards: job 12 ...", "merge: job 13").
job_of() { grep -oP "^$1: job \K[0-9]+" "$2"; }

run_args=(run -n 16 --seed 4 --overlay-bx 3)

# Submits the 4-shard study into folder $1 (more conftrack slurm options
# after it), saving the output in $work/submit-<n>.txt; sets shard_job and
# merge_job.
submissions=0
submit() {
  local folder=$1
  shift
  submissions=$((submissions + 1))
  submitted="$work/submit-$submissions.txt"
  "$conftrack" slurm --shards 4 --no-plots -o "$folder" "$@" -- "${run_args[@]}" |
    tee "$submitted"
  shard_job=$(job_of shards "$submitted" || true)
  merge_job=$(job_of merge "$submitted")
}

# Waits for merge job $1 and compares the report in folder $2 with the
# single-process one.
expect_merged() {
  wait_gone "$1"
  local state
  state=$(job_state "$1")
  [ "$state" = COMPLETED ] || fail "merge job $1 ended $state"
  python3 "$here/compare_reports.py" "$work/single" "$2/merged"
}

# --- the reference: one process
"$conftrack" -q "${run_args[@]}" --no-plots -j 2 -o "$work/single" >/dev/null

# --- 1. four shards and the merge
submit "$work/study"
expect_merged "$merge_job" "$work/study"
echo "slurm test: 4-shard run merged by job $merge_job equals the single-process run"

# --- 2. a failing shard: shard 2 cannot write its folder (a file is there)
mkdir -p "$work/study2"
echo "not a folder" >"$work/study2/shard-2"
submit "$work/study2"
wait_gone "$shard_job"
# The dependency is evaluated by the scheduler loop: give it a moment.
for _ in $(seq 30); do
  [ "$(job_reason "$merge_job")" = DependencyNeverSatisfied ] && break
  sleep 1
done
[ "$(job_state "$merge_job")" = PENDING ] ||
  fail "merge job $merge_job is $(job_state "$merge_job") after a failed shard, not PENDING"
[ "$(job_reason "$merge_job")" = DependencyNeverSatisfied ] ||
  fail "merge job $merge_job waits for $(job_reason "$merge_job"), not DependencyNeverSatisfied"
[ ! -e "$work/study2/merged" ] || fail "a merged report exists although a shard failed"
failed=$(scontrol show job "$shard_job" | grep -c 'JobState=FAILED' || true)
[ "$failed" -eq 1 ] || fail "expected 1 failed shard task, found $failed"
echo "slurm test: shard 2 failed, merge job $merge_job never started (DependencyNeverSatisfied)"

# The user's fix and the README's resume command.
scancel "$merge_job"
rm "$work/study2/shard-2"
submit "$work/study2" --resume
grep -q "array 2 of 4" "$submitted" || fail "resume did not submit shard 2 alone"
expect_merged "$merge_job" "$work/study2"
echo "slurm test: resumed study equals the single-process run"
echo "slurm test: PASSED"
