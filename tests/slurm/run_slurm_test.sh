#!/usr/bin/env bash
# armfarm on a real Slurm: starts a private one-node cluster on this machine (munged, slurmctld,
# slurmd from Debian's slurm-wlm and munge, installed with apt-get when missing), submits a
# six-job sweep with `armfarm slurm --submit` as an array of 3 shard tasks plus the merge,
# waits for them (bounded), and checks that `armfarm compare merged.db local.db` exits 0 against
# a local `armfarm run` of the same spec. The submission has a --setup file (its line must run
# before armfarm, in every task) and a hostile --sbatch-arg=--comment=... value (it must reach
# Slurm as written and run nothing). First one task is cancelled right after submission: the
# merge still runs (afterany), merges the two other shards and names shard 2; then the same
# command again submits only shard 2 and a merge; once more it finds nothing to submit. Then,
# with fake jobs that sleep (the test binary armfarm_fakejobs), in one task each: 4 jobs of 20 s under a
# one-minute --time with the warning 30 s before (the task is warned, lets its running job end,
# requeues itself, until the sweep completes), and 4 jobs of 6 s whose task is requeued with
# `scontrol requeue` while a job runs; both end with every job done exactly once (the task logs'
# progress lines, the merged database). Each wait prints the jobs' states as they change (the
# timeline). About 3 minutes, mostly sleeping.
# Stops the daemons it started, by pid, on every exit path. Skips (exit 0, one line) when not
# root or when the packages cannot be installed.
#
# usage: tests/slurm/run_slurm_test.sh [ARMFARM_BINARY [FAKE_JOBS_BINARY]]
#   (default: build/runner/armfarm and, beside it, armfarm_fakejobs)
# environment: SLURM_TEST_TIMEOUT (s, default 900) bounds the wait for the Slurm jobs.
set -euo pipefail

repo=$(cd "$(dirname "$0")/../.." && pwd)
armfarm=$(realpath "${1:-$repo/build/runner/armfarm}")
fake_jobs_armfarm=$(realpath "${2:-$(dirname "$armfarm")/armfarm_fakejobs}")
spec=$repo/tests/data/specs/slurm_small.json
timeout=${SLURM_TEST_TIMEOUT:-900}
started=$(date +%s)

say() { echo "run_slurm_test: $*"; }
skip() { say "SKIPPED: $*"; exit 0; }

[ "$(id -u)" -eq 0 ] || skip "needs root (it installs packages and starts slurmctld, slurmd and munged)"
[ -x "$armfarm" ] || { say "FAILED: no armfarm binary at $armfarm (build it first: make build)"; exit 1; }
[ -x "$fake_jobs_armfarm" ] || { say "FAILED: no armfarm_fakejobs binary at $fake_jobs_armfarm (build it first: make build)"; exit 1; }

# ---- packages ----
if ! command -v slurmctld >/dev/null || ! command -v slurmd >/dev/null || ! command -v munged >/dev/null ||
   ! command -v sbatch >/dev/null; then
  say "installing slurm-wlm and munge with apt-get"
  if ! { DEBIAN_FRONTEND=noninteractive apt-get update -qq &&
         DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends slurm-wlm munge; } \
       >/tmp/run_slurm_test.apt.log 2>&1; then
    skip "could not install slurm-wlm and munge (apt-get log: /tmp/run_slurm_test.apt.log)"
  fi
fi
say "$(slurmctld -V), $(munged --version 2>&1 | head -1 | awk '{print $1}')"

# ---- a private cluster: every file in one folder, the daemons on their own ports ----
work=$(mktemp -d /tmp/armfarm-slurm-test.XXXXXX)
chmod 0755 "$work"
pids=()
job_ids=()
cleanup() {
  local status=$?
  if [ ${#job_ids[@]} -gt 0 ] && [ -n "${SLURM_CONF:-}" ]; then
    scancel "${job_ids[@]}" 2>/dev/null || true
  fi
  local i
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do  # slurmd, slurmctld, then munged
    kill "${pids[i]}" 2>/dev/null || true
  done
  for pid in "${pids[@]}"; do
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$pid" 2>/dev/null || true
  done
  if [ "$status" -ne 0 ]; then
    say "FAILED (exit $status); logs in $work"
    for log in slurmctld.log slurmd.log munged.log; do
      [ -f "$work/$log" ] && { echo "---- $log (last 20 lines)"; tail -20 "$work/$log"; }
    done
    for log in "$work"/merged.db.slurm-*.log; do
      [ -f "$log" ] && { echo "---- $(basename "$log")"; cat "$log"; }
    done
  else
    rm -rf "$work"
  fi
  exit "$status"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

mkdir -p "$work/munge" "$work/state" "$work/spool"
chmod 0711 "$work/munge"
dd if=/dev/urandom of="$work/munge/munge.key" bs=1024 count=1 status=none
chmod 0400 "$work/munge/munge.key"
munged --foreground --force --key-file="$work/munge/munge.key" --socket="$work/munge/munge.socket" \
  --pid-file="$work/munge/munged.pid" --seed-file="$work/munge/munged.seed" --log-file="$work/munged.log" >"$work/munged.out" 2>&1 &
pids+=($!)
for _ in $(seq 50); do [ -S "$work/munge/munge.socket" ] && break; sleep 0.1; done
[ -S "$work/munge/munge.socket" ] || { say "munged did not start"; exit 1; }

host=$(hostname -s)
# The node line as slurmd measures this machine (CPUs, sockets, cores, memory), so that the
# controller never drains it for a mismatch.
node=$(slurmd -C | head -1 | sed -e "s/^NodeName=[^ ]*/NodeName=$host NodeAddr=127.0.0.1/")
export SLURM_CONF=$work/slurm.conf
cat >"$SLURM_CONF" <<EOF
ClusterName=armfarmtest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=16817
SlurmdPort=16818
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
# cred_expire: also how long a requeued job waits before it may start again (default 120 s).
AuthInfo=socket=$work/munge/munge.socket,cred_expire=15
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
SchedulerParameters=sched_interval=2
MpiDefault=none
SwitchType=switch/none
ReturnToService=2
MinJobAge=3600
KillWait=5
$node State=UNKNOWN
PartitionName=armfarmtest Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF

slurmctld -D -c -f "$SLURM_CONF" >"$work/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" >"$work/slurmd.out" 2>&1 &
pids+=($!)
idle=
for _ in $(seq 120); do
  state=$(sinfo -h -n "$host" -o %T 2>/dev/null || true)
  if [ "$state" = idle ]; then idle=1; break; fi
  sleep 0.5
done
[ -n "$idle" ] || { say "node $host did not become idle (state: ${state:-none})"; exit 1; }
say "one-node cluster up: $(sinfo -h -o '%P %D node(s) %c CPUs %T')"

# ---- the sweep on Slurm, and locally ----
cd "$work"
db=$work/merged.db
deadline=$((started + timeout))
# A site's setup file (module lines there) and an option value that would run code if interpolated.
setup="$work/site setup's.sh"
printf 'echo "site setup ran on $(hostname)"\nexport ARMFARM_SITE=1\n' > "$setup"
hostile="it's \$(touch $work/owned) \"x\" \\ #"

# Submits the sweep $spec into $db with `armfarm slurm "${args[@]}" --submit` and waits until its
# jobs leave the queue, printing each change of their states with the seconds since the
# submission (the timeline); sets array_id, merge_id and merge_state, prints each task's state
# and log. $1...: a command to run once the jobs are submitted (while they run).
submit_and_wait() {
  local submitted
  submitted=$("$armfarm" slurm "$spec" --db "$db" "${args[@]}" --submit)
  echo "$submitted"
  array_id=$(sed -n 's/^submitted array job \([0-9]*\).*/\1/p' <<<"$submitted")
  merge_id=$(sed -n 's/^submitted merge job \([0-9]*\).*/\1/p' <<<"$submitted")
  [ -n "$array_id" ] && [ -n "$merge_id" ] || { say "no job ids in the output of armfarm slurm --submit"; exit 1; }
  job_ids=("$array_id" "$merge_id")
  submitted_at=$(date +%s)
  [ -z "${1:-}" ] || "$@"  # work to do while the jobs run
  local states last=
  while true; do
    states=$(squeue -h -j "$array_id,$merge_id" -o '%i %T %r' 2>/dev/null | sort | paste -sd ';' || true)
    [ "$states" = "$last" ] || echo "  timeline +$(($(date +%s) - submitted_at)) s: ${states:-(none in the queue)}"
    last=$states
    [ -n "$states" ] || break
    if [ "$(date +%s)" -gt "$deadline" ]; then
      say "timed out after ${timeout}s waiting for jobs $array_id and $merge_id:"
      squeue -j "$array_id,$merge_id" || true
      exit 1
    fi
    sleep 1
  done
  job_ids=()
  scontrol -o show job "$array_id" | awk '{
      for (i = 1; i <= NF; i++) { split($i, kv, "="); field[kv[1]] = kv[2] }
      printf "  array task %s (job %s): %s, exit %s, restarts %s\n", field["ArrayTaskId"], field["JobId"], field["JobState"], field["ExitCode"], field["Restarts"]
    }' | sort
  merge_state=$(scontrol -o show job "$merge_id" | sed -n 's/.*JobState=\([A-Z_]*\) .*/\1/p')
  say "merge job $merge_id: $merge_state"
  local log
  for log in "$db".slurm-"$array_id"_*.log "$db".slurm-"$merge_id"-merge.log; do
    [ -f "$log" ] && { echo "---- $(basename "$log")"; cat "$log"; }
  done
  return 0
}
# Fails unless every job of $spec is done in $db and was done exactly once in the task logs $@
# (a job done twice would show two "done" progress lines; a lost one none).
check_each_job_done_once() {
  local key count
  for key in $("$armfarm" expand "$spec" | awk 'NR > 1 {print $1}'); do
    count=$(cat "$@" | grep -c "] done  *${key:0:8} " || true)
    [ "$count" -eq 1 ] || { say "job ${key:0:8} was done $count times in the task logs"; exit 1; }
    [ "$(sqlite3 "$db" "select status from jobs where key = '$key'")" = done ] ||
      { say "job ${key:0:8} is not done in $db"; exit 1; }
  done
}
local_run() {
  say "local run of the same spec"
  "$armfarm" run "$spec" --db "$work/local.db" -j 1 2>/dev/null
}

cancel_task_2() {
  scancel "${array_id}_1"
  say "cancelled array task 1 (shard 2)"
  local_run
}
spec=$repo/tests/data/specs/slurm_small.json
args=(--tasks 3 --cpus-per-task 1 --time 30 --setup "$setup" --sbatch-arg="--comment=$hostile")
say "1. array task 1 (shard 2) cancelled right after submission: the merge merges shards 1 and 3 and names shard 2"
submit_and_wait cancel_task_2
[ "$merge_state" = FAILED ] || { say "the merge job ended $merge_state, expected FAILED (exit 1: a shard missing)"; exit 1; }
[ -e "$db" ] || { say "$db was not written by the partial merge"; exit 1; }
grep -q "merged 2 of 3 shards; 1 did not save their results (shard 2;" "$db.slurm-$merge_id-merge.log" ||
  { say "the merge log does not name shard 2"; exit 1; }
grep -q "^armfarm slurm: 4 of 6 jobs of sweep slurm_small finished in $db; 2 missing, in shard 2 of 3:" "$db.slurm-$merge_id-merge.log" ||
  { say "the merge log does not count the missing jobs"; exit 1; }
[ "$(grep -c "^  shard 2: " "$db.slurm-$merge_id-merge.log")" -eq 2 ] || { say "the merge log does not name the 2 missing jobs"; exit 1; }
[ ! -e "$work/owned" ] || { say "the hostile --sbatch-arg value ran as code"; exit 1; }
scontrol -o show job "$merge_id" | grep -qF "Comment=it's \$(touch $work/owned)" ||
  { say "the hostile --comment did not reach Slurm as written: $(scontrol -o show job "$merge_id" | grep -o 'Comment=.*')"; exit 1; }
for task in 0 2; do
  log="$db.slurm-${array_id}_$task.log"
  grep -q "^site setup ran on" "$log" || { say "task $task: the --setup line did not run"; exit 1; }
  [ "$(grep -n -m1 "^site setup ran on" "$log" | cut -d: -f1)" -lt "$(grep -n -m1 "^armfarm slurm: shard" "$log" | cut -d: -f1)" ] ||
    { say "task $task: the --setup line ran after armfarm"; exit 1; }
done

say "2. the same command again: only shard 2 is submitted, then the merge"
submit_and_wait
[ "$merge_state" = COMPLETED ] || { say "the merge job did not complete"; exit 1; }
for task in 0 2; do
  [ ! -e "$db.slurm-${array_id}_$task.log" ] || { say "task $task ran again although its shard was complete"; exit 1; }
done
[ -e "$db.slurm-${array_id}_1.log" ] || { say "shard 2 did not run"; exit 1; }
say "armfarm compare merged.db local.db"
"$armfarm" compare "$db" "$work/local.db"

say "3. the same command once more: nothing to submit"
again=$("$armfarm" slurm "$spec" --db "$db" --tasks 3 --submit)
echo "$again"
grep -q "nothing to submit" <<<"$again" || { say "submitting again found work to do"; exit 1; }

# Fake jobs from here on (they sleep: cheap on CPU), in sweeps of one task.
armfarm=$fake_jobs_armfarm
say "4. a task past its time limit: 4 jobs of 20 s in one task with --time 1 (60 s), warned 30 s before"
spec=$repo/tests/data/specs/slurm_timed.json
db=$work/timed.db
args=(--tasks 1 --time 1 --signal-before 30)
submit_and_wait
[ "$merge_state" = COMPLETED ] || { say "the merge job ended $merge_state, expected COMPLETED"; exit 1; }
grep -q "^armfarm slurm: shard 1/1 requeued" "$db.slurm-${array_id}_0.log" || { say "the task was not requeued"; exit 1; }
check_each_job_done_once "$db.slurm-${array_id}_0.log"

say "5. scontrol requeue while a job runs: 4 jobs of 6 s in one task"
spec=$repo/tests/data/specs/slurm_requeue.json
db=$work/requeue.db
args=(--tasks 1 --time 10)
requeue_mid_job() {
  local shard_db=$db.shard-1.db
  # Read only once armfarm made the file (sqlite3 would create an empty one, which armfarm refuses).
  until [ -s "$shard_db" ] &&
        [ "$(sqlite3 -readonly "$shard_db" "select count(*) from jobs where status = 'done'" 2>/dev/null || echo 0)" -ge 1 ]; do
    [ "$(date +%s)" -le "$deadline" ] || { say "timed out waiting for the first job of $shard_db"; exit 1; }
    sleep 0.5
  done
  sleep 2  # the second job is running
  scontrol requeue "${array_id}_0"
  say "scontrol requeue ${array_id}_0 at +$(($(date +%s) - submitted_at)) s, the second job running"
}
submit_and_wait requeue_mid_job
[ "$merge_state" = COMPLETED ] || { say "the merge job ended $merge_state, expected COMPLETED"; exit 1; }
[ "$(scontrol -o show job "$array_id" | sed -n 's/.* Restarts=\([0-9]*\) .*/\1/p')" -ge 1 ] ||
  { say "the task did not restart"; exit 1; }
check_each_job_done_once "$db.slurm-${array_id}_0.log"
say "PASSED in $(($(date +%s) - started)) s"
