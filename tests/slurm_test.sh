#!/usr/bin/env bash
# metamer batch on a real Slurm (docs/batch.md, "Slurm"): starts a single-node cluster (munged,
# slurmctld, slurmd from Debian, in a temporary folder, recipe of shared/notes/slurm.md), writes a
# 48-job sweep's job array with `metamer batch --slurm --tasks 4`, submits it, cancels one array
# task mid-run, checks that what it left is whole, resubmits, checks that only the missing jobs
# were rendered, and compares the merged index and every output file, byte for byte, with a local
# `metamer batch` of the same sweep. Every daemon it started is stopped by its PID, whatever the
# outcome. Usage: slurm_test.sh METAMER_BINARY SOURCE_DIR
set -uo pipefail
metamer="$1"
src="$2"
for tool in munged slurmctld slurmd sbatch squeue scontrol scancel sinfo; do
  command -v "$tool" >/dev/null || { echo "slurm_test: $tool is not installed (ci/setup.sh installs Slurm)"; exit 1; }
done

W=$(mktemp -d -t metamer-slurm.XXXXXX)
chmod 755 "$W"
H=$(hostname -s)
mkdir -p "$W"/{state,"spool/slurmd.$H",log,munge,data}
chmod 755 "$W/munge"
export SLURM_CONF="$W/slurm.conf"
MUNGE_PID="" CTLD_PID="" SLURMD_PID=""

fail() {
  echo "slurm_test: FAIL: $*"
  for f in "$W"/log/*.log "$W"/log/*.out "$W"/data/cluster/slurm/logs/*.log; do
    [ -f "$f" ] && { echo "--- $f"; tail -n 30 "$f"; }
  done
  exit 1
}

stop() {
  # Jobs first (slurmstepd outlives the daemons), then the daemons by PID, newest first.
  if [ -n "$CTLD_PID" ] && kill -0 "$CTLD_PID" 2>/dev/null; then
    if [ -n "$(squeue -h -o %i 2>/dev/null)" ]; then
      scancel --user=root 2>/dev/null
      for _ in $(seq 1 100); do [ -z "$(squeue -h -o %i 2>/dev/null)" ] && break; sleep 0.1; done
    fi
  fi
  # The safety net: step daemons still holding a socket in our spool folder, killed by PID.
  for sock in "$W/spool/slurmd.$H"/*_*; do
    [ -S "$sock" ] || continue
    for pid in $(ss -xlpH src "$sock" 2>/dev/null | grep -o 'pid=[0-9]*' | cut -d= -f2); do kill -KILL "$pid" 2>/dev/null; done
  done
  for pid in $SLURMD_PID $CTLD_PID $MUNGE_PID; do
    [ -n "$pid" ] && kill -TERM "$pid" 2>/dev/null && wait "$pid" 2>/dev/null
  done
  rm -rf "$W"
}
trap stop EXIT

# --- the cluster
dd if=/dev/urandom of="$W/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$W/munge/munge.key"
munged -F --socket="$W/munge/munge.socket" --key-file="$W/munge/munge.key" --pid-file="$W/munge/munged.pid" \
       --log-file="$W/log/munged.log" --seed-file="$W/munge/munged.seed" > "$W/log/munged.out" 2>&1 &
MUNGE_PID=$!
for _ in $(seq 1 100); do munge -n -S "$W/munge/munge.socket" 2>/dev/null | unmunge -S "$W/munge/munge.socket" >/dev/null 2>&1 && break; sleep 0.05; done
mem=$(awk '/MemTotal/ {printf "%d", $2 / 1024 * 0.9}' /proc/meminfo)
cat > "$SLURM_CONF" <<EOF
ClusterName=metamer-ci
SlurmctldHost=$H(127.0.0.1)
SlurmctldPort=16817
SlurmdPort=16818
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$W/munge/munge.socket
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$W/state
SlurmdSpoolDir=$W/spool/slurmd.%n
SlurmctldPidFile=$W/slurmctld.pid
SlurmdPidFile=$W/slurmd.%n.pid
SlurmctldLogFile=$W/log/slurmctld.log
SlurmdLogFile=$W/log/slurmd.%n.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
SchedulerParameters=batch_sched_delay=0
MpiDefault=none
MailProg=/bin/true
ReturnToService=2
MinJobAge=300
KillWait=5
InactiveLimit=0
NodeName=$H NodeAddr=127.0.0.1 CPUs=$(nproc) RealMemory=$mem State=UNKNOWN
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
slurmctld -D -f "$SLURM_CONF" > "$W/log/slurmctld.out" 2>&1 &
CTLD_PID=$!
for _ in $(seq 1 200); do scontrol ping 2>/dev/null | grep -q "is UP" && break; kill -0 $CTLD_PID 2>/dev/null || fail "slurmctld died"; sleep 0.05; done
slurmd -D -f "$SLURM_CONF" -N "$H" > "$W/log/slurmd.out" 2>&1 &
SLURMD_PID=$!
for _ in $(seq 1 200); do [ "$(sinfo -h -n "$H" -o %T 2>/dev/null)" = "idle" ] && break; kill -0 $SLURMD_PID 2>/dev/null || fail "slurmd died"; sleep 0.05; done
[ "$(sinfo -h -n "$H" -o %T)" = "idle" ] || fail "the node is not idle: $(sinfo -R)"
echo "slurm_test: cluster up on $H"

# Waits until none of the given jobs is queued or running (at most $2 seconds).
wait_jobs() {
  local ids="$1" limit="$2" start=$SECONDS
  while [ -n "$(squeue -h -j "$ids" -o %i 2>/dev/null)" ]; do
    [ $((SECONDS - start)) -gt "$limit" ] && fail "jobs $ids still queued after ${limit} s: $(squeue)"
    case "$(sinfo -h -n "$H" -o %T)" in drain*|down*) fail "the node drained: $(sinfo -R)";; esac
    sleep 0.2
  done
}
records() { find "$W/data/$1" -name job.json 2>/dev/null | wc -l; }

# --- the sweep: 12 lights × 2 detectors × 2 adaptations = 48 jobs, a cube and a PNG each (12 a
# task: long enough for task 1 to be cancelled while it runs)
lights='"illuminants/D65","illuminants/A","illuminants/FL2","illuminants/D50","illuminants/E","illuminants/FL11","illuminants/FL1","illuminants/FL3","illuminants/FL4","illuminants/FL5","illuminants/FL6","illuminants/FL7"'
cat > "$W/data/sweep.json" <<EOF
{"scenes": ["$src/tests/data/cli/small.json"], "render": {"write": "cube,png", "size": "256x192"},
 "axes": [{"name": "light", "set": "lights.1.spectrum", "values": [$lights]},
          {"render": "detector", "values": ["cie1931", "cie1964"]},
          {"render": "adapt", "values": ["bradford", "cat16"]}]}
EOF
"$metamer" batch "$W/data/sweep.json" --out "$W/data/local" -q > "$W/log/local.out" 2>&1 || fail "the local batch failed: $(cat "$W/log/local.out")"
[ "$(records local)" = 48 ] || fail "the local batch recorded $(records local) jobs, not 48"

# --- the array: 4 tasks, one cancelled mid-run
"$metamer" batch "$W/data/sweep.json" --out "$W/data/cluster" --slurm --tasks 4 > "$W/log/slurm-write.out" 2>&1 \
  || fail "metamer batch --slurm failed: $(cat "$W/log/slurm-write.out")"
grep -q "48 jobs, all valid, in 4 array tasks" "$W/log/slurm-write.out" || fail "unexpected: $(cat "$W/log/slurm-write.out")"
t0=$SECONDS
ids=$(sh "$W/data/cluster/slurm/submit.sh") || fail "submit.sh failed: $ids"
array=$(echo "$ids" | awk '{print $2}')
index=$(echo "$ids" | awk '{print $4}')
echo "slurm_test: submitted array $array (4 tasks) and index $index"
# Cancel task 1 once it has recorded its first job.
for _ in $(seq 1 600); do
  grep -l '"shard": "1/4"' "$W"/data/cluster/*/job.json >/dev/null 2>&1 && break
  sleep 0.02
done
scancel "${array}_1" || fail "scancel ${array}_1 failed"
wait_jobs "$array,$index" 300
first=$(records cluster)
echo "slurm_test: first submission: $first of 48 jobs recorded in $((SECONDS - t0)) s (task 1 cancelled)"
[ "$first" -lt 48 ] || fail "task 1 finished before it was cancelled: nothing left to resume"
[ "$first" -ge 1 ] || fail "nothing was recorded"
state=$(scontrol -o show job "${array}_1" | grep -o 'JobState=[A-Z]*')
[ "$state" = "JobState=CANCELLED" ] || fail "task 1 is $state, not cancelled"
# What the cancelled task left is whole: no temporary file, every recorded job's outputs present.
[ -z "$(find "$W/data/cluster" -name '.*.tmp-*')" ] || fail "temporary files left: $(find "$W/data/cluster" -name '.*.tmp-*')"

# --- the resubmission renders only the missing jobs
t0=$SECONDS
ids=$(sh "$W/data/cluster/slurm/submit.sh") || fail "submit.sh (again) failed: $ids"
array2=$(echo "$ids" | awk '{print $2}')
index2=$(echo "$ids" | awk '{print $4}')
wait_jobs "$array2,$index2" 300
echo "slurm_test: resubmission finished in $((SECONDS - t0)) s"
rendered=0
for task in 0 1 2 3; do
  log="$W/data/cluster/slurm/logs/task-${array2}_${task}.log"
  line=$(grep -o '[0-9]* rendered, [0-9]* skipped (done before), [0-9]* failed' "$log") || fail "no summary in $log"
  echo "slurm_test:   task $task: $line"
  rendered=$((rendered + $(echo "$line" | awk '{print $1}')))
  echo "$line" | grep -q ' 0 failed' || fail "task $task: $line"
done
[ "$rendered" -eq $((48 - first)) ] || fail "the resubmission rendered $rendered jobs; $((48 - first)) were missing"
for task in 0 1 2 3; do
  state=$(scontrol -o show job "${array2}_${task}" | grep -o 'JobState=[A-Z]*')
  [ "$state" = "JobState=COMPLETED" ] || fail "resubmitted task $task is $state"
done

# --- the merged index and every file against the local batch
[ -f "$W/data/cluster/index.csv" ] || fail "the index job wrote no index"
cut -d, -f1,2 "$W/data/local/index.csv" > "$W/log/local-ids"
cut -d, -f1,2 "$W/data/cluster/index.csv" > "$W/log/cluster-ids"
cmp -s "$W/log/local-ids" "$W/log/cluster-ids" || fail "the indexes list different jobs: $(diff "$W/log/local-ids" "$W/log/cluster-ids")"
[ "$(grep -c ',done,' "$W/data/cluster/index.csv")" = 48 ] || fail "not every job is done in the index"
files=0
while read -r id; do
  for f in small.exr small.png; do
    cmp -s "$W/data/local/$id/$f" "$W/data/cluster/$id/$f" || fail "$id/$f differs from the local batch's"
    files=$((files + 1))
  done
done < <(tail -n +2 "$W/data/local/index.csv" | cut -d, -f1)
echo "slurm_test: PASS: 48 jobs in 4 array tasks; task 1 cancelled after $first jobs were recorded; the resubmission rendered the $rendered missing; index and $files files equal to the local batch's"
exit 0
