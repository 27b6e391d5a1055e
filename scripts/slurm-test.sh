#!/usr/bin/env bash
# Proves that docs/distributed.md's Slurm recipe works: brings up a single-node Slurm on this
# machine, renders one image as a job array of 4 shards plus a dependent merge job, and checks
# the merged image against the same image rendered in one process. Then it checks preemption:
# a second array whose shard 0 is sent SIGTERM mid-render (as `--signal`/preemption would) must
# write its checkpoint, requeue itself, resume and still produce the bit-identical shard.
#
# Usage (as root, on Debian 12):  scripts/slurm-test.sh [VKPATH_BINARY] [WORK_DIR]
#   VKPATH_BINARY defaults to target/release/vkpath; WORK_DIR to a new temporary folder.
#
# What it does to the machine: installs slurm-wlm and munge with apt-get if they are missing,
# creates /etc/munge/munge.key if missing, writes /etc/slurm/slurm.conf (an existing one it did
# not write is saved and put back at the end), uses /var/spool/slurmctld, /var/spool/slurmd and
# /var/log/slurm, and starts munged (unless one already answers), slurmctld and slurmd as plain
# daemons (no systemd needed). It stops the daemons it started when it exits, however it exits.
# It refuses to run where a slurmctld or slurmd is already running (that is someone's Slurm).
#
# Every wait is bounded (node up: 60 s; jobs: 300 s each phase), so it never hangs.
# Exit status: 0 PASS, 1 FAIL, 2 could not set up Slurm / bad usage.
#
# Not part of CI (scripts/test.sh, cargo test): CI machines have no Slurm, and installing and
# starting three daemons as root there is slow and fragile. Run it by hand after changing
# sharding, merge, checkpoints or signal handling, and before changing docs/distributed.md.
set -uo pipefail

top=$(cd "$(dirname "$0")/.." && pwd)
vk_arg=${1:-$top/target/release/vkpath}
if [ ! -x "$vk_arg" ]; then
  echo "slurm-test: no executable vkpath at '$vk_arg' (build it with cargo build --release)" >&2
  exit 2
fi
VKPATH=$(realpath "$vk_arg")
export VKPATH
work=${2:-$(mktemp -d /tmp/vkpath-slurm-test.XXXXXX)}
mkdir -p "$work"
work=$(realpath "$work")
chmod 755 "$work"

if [ "$(id -u)" != 0 ]; then
  echo "slurm-test: run as root (it installs packages and starts Slurm's daemons)" >&2
  exit 2
fi

log() { printf '[slurm-test %s] %s\n' "$(date +%H:%M:%S)" "$*"; }
failures=()
fail() { failures+=("$*"); log "FAIL: $*"; }
pass() { log "ok: $*"; }

# ---------------------------------------------------------------- packages
missing=()
for pkg in slurm-wlm munge; do
  dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q 'install ok installed' || missing+=("$pkg")
done
if [ ${#missing[@]} -gt 0 ]; then
  log "installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  if ! { timeout 300 apt-get update -qq && timeout 600 apt-get install -y -qq --no-install-recommends "${missing[@]}"; } >"$work/apt.log" 2>&1; then
    tail -20 "$work/apt.log" >&2
    echo "slurm-test: apt-get failed (log: $work/apt.log)" >&2
    exit 2
  fi
fi
for tool in munged munge unmunge slurmctld slurmd sbatch squeue sinfo scontrol scancel; do
  command -v "$tool" >/dev/null || { echo "slurm-test: $tool not found after installing" >&2; exit 2; }
done

if pgrep -x slurmctld >/dev/null || pgrep -x slurmd >/dev/null; then
  echo "slurm-test: a slurmctld or slurmd is already running here; this script sets up its own" >&2
  echo "single-node Slurm and will not touch an existing one. Stop it first." >&2
  exit 2
fi

# ---------------------------------------------------------------- teardown (always)
started_munged=0
started_ctld=0
started_slurmd=0
conf=/etc/slurm/slurm.conf
conf_backup=
marker="# Written by vkpath scripts/slurm-test.sh"
stop_pidfile() { # NAME PIDFILE: TERM, wait up to 15 s, then KILL
  local name=$1 pidfile=$2 pid i
  [ -f "$pidfile" ] || return 0
  pid=$(cat "$pidfile" 2>/dev/null) || return 0
  [ -n "$pid" ] && kill -0 "$pid" 2>/dev/null || return 0
  kill -TERM "$pid" 2>/dev/null
  for i in $(seq 30); do kill -0 "$pid" 2>/dev/null || break; sleep 0.5; done
  if kill -0 "$pid" 2>/dev/null; then kill -KILL "$pid" 2>/dev/null; log "killed $name ($pid)"; else log "stopped $name ($pid)"; fi
}
cleanup() {
  local rc=$?
  trap - EXIT INT TERM HUP
  if [ "$started_ctld" = 1 ] && [ -n "${all_jobs:-}" ]; then
    scancel $all_jobs 2>/dev/null || true
  fi
  [ "$started_slurmd" = 1 ] && stop_pidfile slurmd /run/slurmd.pid
  [ "$started_ctld" = 1 ] && stop_pidfile slurmctld /run/slurmctld.pid
  [ "$started_munged" = 1 ] && stop_pidfile munged /run/munge/munged.pid
  if [ -n "$conf_backup" ]; then mv -f "$conf_backup" "$conf"; log "restored the previous $conf"; fi
  exit "$rc"
}
trap cleanup EXIT
trap 'log "interrupted"; exit 1' INT TERM HUP

# ---------------------------------------------------------------- munge
if [ ! -s /etc/munge/munge.key ]; then
  log "creating /etc/munge/munge.key"
  mkdir -p /etc/munge
  if command -v mungekey >/dev/null; then
    mungekey --create --keyfile=/etc/munge/munge.key --force
  else
    dd if=/dev/urandom of=/etc/munge/munge.key bs=1 count=1024 status=none
  fi
  chown munge:munge /etc/munge/munge.key
  chmod 400 /etc/munge/munge.key
fi
if munge -n 2>/dev/null | unmunge >/dev/null 2>&1; then
  log "munged already running; using it"
else
  mkdir -p /run/munge /var/lib/munge /var/log/munge
  chown munge:munge /run/munge /var/lib/munge /var/log/munge
  chmod 755 /run/munge
  log "starting munged"
  runuser -u munge -- /usr/sbin/munged || { echo "slurm-test: munged did not start" >&2; exit 2; }
  started_munged=1
  for i in $(seq 20); do munge -n 2>/dev/null | unmunge >/dev/null 2>&1 && break; sleep 0.5; done
  munge -n 2>/dev/null | unmunge >/dev/null 2>&1 || { echo "slurm-test: munge does not answer" >&2; exit 2; }
fi

# ---------------------------------------------------------------- slurm.conf
host=$(hostname -s)
cpus=$(nproc)
total_mb=$(free -m | awk '/^Mem:/ {print $2}')
margin=$(( total_mb / 10 > 512 ? total_mb / 10 : 512 ))
mem=$(( total_mb - margin ))
[ "$mem" -gt 100 ] || mem=100
mkdir -p /etc/slurm /var/spool/slurmctld /var/spool/slurmd /var/log/slurm
if [ -f "$conf" ] && ! head -1 "$conf" | grep -qF "$marker"; then
  conf_backup="$conf.vkpath-test-backup"
  cp -p "$conf" "$conf_backup"
  log "saved the existing $conf as $conf_backup"
fi
cat >"$conf" <<EOF
$marker: a single-node test cluster.
ClusterName=vkpathtest
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
ReturnToService=2
StateSaveLocation=/var/spool/slurmctld
SlurmdSpoolDir=/var/spool/slurmd
SlurmctldPidFile=/run/slurmctld.pid
SlurmdPidFile=/run/slurmd.pid
SlurmctldLogFile=/var/log/slurm/slurmctld.log
SlurmdLogFile=/var/log/slurm/slurmd.log
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
MinJobAge=600
KillWait=30
NodeName=$host CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
log "wrote $conf (node $host, CPUs=$cpus, RealMemory=$mem MB)"

# ---------------------------------------------------------------- daemons
log "starting slurmctld"
# -i: start even if the state files of an earlier run cannot be read (job ids continue).
slurmctld -i || { tail -20 /var/log/slurm/slurmctld.log >&2; echo "slurm-test: slurmctld did not start" >&2; exit 2; }
started_ctld=1
log "starting slurmd"
slurmd || { tail -20 /var/log/slurm/slurmd.log >&2; echo "slurm-test: slurmd did not start" >&2; exit 2; }
started_slurmd=1

state=
resumed=0
for i in $(seq 60); do
  state=$(sinfo -h -N -n "$host" -o '%T' 2>/dev/null | head -1)
  [ "$state" = idle ] && break
  if [ "$i" = 30 ] && [ "$resumed" = 0 ] && [[ "$state" == drain* || "$state" == down* ]]; then
    scontrol update NodeName="$host" State=RESUME 2>/dev/null || true
    resumed=1
  fi
  sleep 1
done
if [ "$state" != idle ]; then
  echo "slurm-test: node $host is '$state', not idle, after 60 s" >&2
  sinfo -N -l >&2 || true
  tail -15 /var/log/slurm/slurmctld.log /var/log/slurm/slurmd.log >&2
  exit 2
fi
log "node $host is idle"
sinfo

# ---------------------------------------------------------------- helpers for jobs
all_jobs=
# wait_jobs SECONDS JOBID...: until none is in squeue, or a job waits on a dependency that can
# never be satisfied. Returns 1 on timeout.
wait_jobs() {
  local limit=$1; shift
  local ids; ids=$(IFS=,; echo "$*")
  local deadline=$(( $(date +%s) + limit ))
  while [ "$(date +%s)" -lt "$deadline" ]; do
    local left; left=$(squeue -h -j "$ids" -o '%i %T %r' 2>/dev/null)
    [ -z "$left" ] && return 0
    if grep -q DependencyNeverSatisfied <<<"$left"; then log "a dependency can never be satisfied:"; echo "$left"; return 0; fi
    sleep 2
  done
  log "jobs still queued after $limit s:"; squeue -j "$ids" || true
  return 1
}
# job_states JOBID: the JobState of the job (every task of an array), one a line.
job_states() { scontrol -o show job "$1" 2>/dev/null | grep -o 'JobState=[A-Z_]*' | cut -d= -f2; }
all_completed() { # JOBID EXPECTED_COUNT
  local states; states=$(job_states "$1")
  [ "$(grep -c '^COMPLETED$' <<<"$states")" = "$2" ] && [ "$(wc -l <<<"$states")" = "$2" ]
}
show_logs() { local f; for f in "$@"; do [ -f "$f" ] && { echo "--- $f"; tail -20 "$f"; }; done; }

# The shard job script of docs/distributed.md (Slurm section), word for word: the image
# settings come from the environment (RENDER_ARGS, VKPATH, CHECKPOINT_INTERVAL).
cat >"$work/shard.sbatch" <<'EOF'
#!/bin/bash
#SBATCH --job-name=vkpath-shard
#SBATCH --cpus-per-task=1
#SBATCH --output=shard-%a.log
#SBATCH --requeue
#SBATCH --open-mode=append
#SBATCH --signal=B:TERM@120
# One shard of the image: samples floor(spp*i/n)..floor(spp*(i+1)/n).
set -u
i=$SLURM_ARRAY_TASK_ID
n=$SLURM_ARRAY_TASK_COUNT
args=(render $RENDER_ARGS --shard "$i/$n" -o "shard-$i.exr"
      --checkpoint "ck-$i.exr" --checkpoint-interval "${CHECKPOINT_INTERVAL:-60}" --quiet)
# Resume only when an earlier run of this task (requeued or preempted) left a checkpoint.
[ -f "ck-$i.exr" ] && args+=(--resume "ck-$i.exr")
"$VKPATH" "${args[@]}" &
pid=$!
# Slurm signals this shell (--signal=B:..., scancel --batch, preemption); pass it on.
trap 'kill -TERM $pid 2>/dev/null' TERM INT HUP
wait $pid; rc=$?
# A trapped signal ends the first wait early; wait again for vkpath to write its files.
if kill -0 $pid 2>/dev/null || [ $rc -gt 128 ]; then wait $pid; rc=$?; fi
echo "vkpath exited $rc (restart ${SLURM_RESTART_COUNT:-0})"
if [ $rc -ge 129 ] && [ $rc -le 131 ] || [ $rc = 143 ]; then
  # Stopped by a signal: the checkpoint is written. Queue this task again; it resumes.
  scontrol requeue "$SLURM_JOB_ID"
  exit 0
fi
exit $rc
EOF

cat >"$work/merge.sbatch" <<'EOF'
#!/bin/bash
#SBATCH --job-name=vkpath-merge
#SBATCH --cpus-per-task=1
#SBATCH --output=merge.log
set -eu
"$VKPATH" merge shard-*.exr -o image.exr
"$VKPATH" merge shard-*.exr -o image.png
EOF

# ---------------------------------------------------------------- phase 1: 4 shards + merge
p1="$work/phase1"
mkdir -p "$p1"
cd "$p1"
export RENDER_ARGS="--width 64 --height 64 --spp 256"
export CHECKPOINT_INTERVAL=60
log "phase 1: job array of 4 shards ($RENDER_ARGS, built-in Cornell box) and a dependent merge job in $p1"
arr=$(sbatch --parsable --array=0-3 "$work/shard.sbatch" | cut -d';' -f1)
merge=$(sbatch --parsable --dependency=afterok:"$arr" "$work/merge.sbatch" | cut -d';' -f1)
all_jobs="$arr $merge"
log "submitted array job $arr and merge job $merge (afterok:$arr)"
squeue || true
if ! wait_jobs 300 "$arr" "$merge"; then
  fail "phase 1 jobs did not finish within 300 s"
  scancel "$arr" "$merge" 2>/dev/null || true
fi
log "array tasks: $(job_states "$arr" | sort | uniq -c | tr '\n' ' ')  merge: $(job_states "$merge")"
if all_completed "$arr" 4; then pass "4 shard tasks COMPLETED"; else fail "not every shard task COMPLETED"; show_logs shard-*.log; fi
if all_completed "$merge" 1 && [ -s image.exr ] && [ -s image.png ]; then
  pass "merge job COMPLETED: $(tail -1 merge.log 2>/dev/null)"
else
  fail "merge job did not complete or wrote no image"; show_logs merge.log
fi

log "rendering the same image in one process"
"$VKPATH" render $RENDER_ARGS -o single.exr --quiet || fail "single render failed"
"$VKPATH" render $RENDER_ARGS -o single.png --quiet || fail "single PNG render failed"
if [ -s image.exr ] && [ -s single.exr ]; then
  if "$VKPATH" compare image.exr single.exr >compare.txt 2>&1; then
    pass "vkpath compare merged.exr single.exr: $(head -1 compare.txt)"
  else
    fail "vkpath compare merged vs single (8x8 blocks): $(head -1 compare.txt)"; cat compare.txt
  fi
  if "$VKPATH" compare --alpha 0.01 --block 1 --json image.exr single.exr >compare-pixels.json 2>/dev/null; then
    pass "vkpath compare --alpha 0.01 --block 1 (every pixel): consistent; worst $(tr -d ' \n' <compare-pixels.json | grep -o '"worst":{[^}]*}')"
  else
    fail "vkpath compare --alpha 0.01 --block 1 (every pixel) says inconsistent"; cat compare-pixels.json
  fi
  # The files themselves differ by design (a merged EXR also carries the render state, so it
  # can be merged again); the per-pixel test above is what compares their radiance.
  log "info: image.exr is $(stat -c %s image.exr) bytes (radiance + merge state), single.exr $(stat -c %s single.exr) (radiance only)"
fi
if [ -s image.png ] && [ -s single.png ]; then
  if cmp -s image.png single.png; then pass "merged PNG and single-process PNG are identical"
  else log "note (not a failure): the PNGs differ in $(cmp -l image.png single.png 2>/dev/null | wc -l) bytes"; fi
fi

# ---------------------------------------------------------------- phase 2: preempt a shard
p2="$work/phase2"
mkdir -p "$p2"
cd "$p2"
export RENDER_ARGS="--width 96 --height 96 --spp 4096"
export CHECKPOINT_INTERVAL=1
log "phase 2: job array of 2 shards ($RENDER_ARGS); shard 0 gets SIGTERM mid-render, must checkpoint, requeue and resume"
arr2=$(sbatch --parsable --array=0-1 "$work/shard.sbatch" | cut -d';' -f1)
merge2=$(sbatch --parsable --dependency=afterok:"$arr2" "$work/merge.sbatch" | cut -d';' -f1)
all_jobs="$all_jobs $arr2 $merge2"
log "submitted array job $arr2 and merge job $merge2"
signalled=0
deadline=$(( $(date +%s) + 120 ))
while [ "$(date +%s)" -lt "$deadline" ]; do
  if [ -s ck-0.exr ] && [ "$(job_states "${arr2}_0" | head -1)" = RUNNING ]; then
    log "shard 0 is running and has a checkpoint; sending SIGTERM to its batch shell (as preemption would)"
    scancel --batch --signal=TERM "${arr2}_0" && signalled=1
    break
  fi
  [ -s shard-0.exr ] && break
  sleep 0.5
done
[ "$signalled" = 1 ] || fail "shard 0 could not be signalled mid-render (finished first or never started)"
if ! wait_jobs 300 "$arr2" "$merge2"; then
  fail "phase 2 jobs did not finish within 300 s"
  scancel "$arr2" "$merge2" 2>/dev/null || true
fi
restarts=$(scontrol -o show job "${arr2}_0" 2>/dev/null | grep -o 'Restarts=[0-9]*' | cut -d= -f2)
log "array tasks: $(job_states "$arr2" | sort | uniq -c | tr '\n' ' ')  merge: $(job_states "$merge2")  shard 0 restarts: ${restarts:-?}"
show_logs shard-0.log
if [ "$signalled" = 1 ]; then
  if grep -q 'stopped by SIGTERM' shard-0.log 2>/dev/null && [ "${restarts:-0}" -ge 1 ]; then
    pass "shard 0 stopped on SIGTERM, wrote its checkpoint and was requeued (restarts=$restarts)"
  else
    fail "shard 0 was not stopped by SIGTERM and requeued"
  fi
fi
if all_completed "$arr2" 2 && all_completed "$merge2" 1 && [ -s image.exr ]; then
  pass "phase 2 shards and merge COMPLETED"
else
  fail "phase 2 shards or merge did not complete"; show_logs shard-*.log merge.log
fi
log "rendering shard 0 uninterrupted, and the whole image in one process"
"$VKPATH" render $RENDER_ARGS --shard 0/2 -o shard-0-uninterrupted.exr --quiet || fail "uninterrupted shard render failed"
if [ -s shard-0.exr ] && cmp -s shard-0.exr shard-0-uninterrupted.exr; then
  pass "the preempted-and-resumed shard 0 is byte-identical to an uninterrupted one"
else
  fail "the resumed shard 0 differs from an uninterrupted one"
fi
"$VKPATH" render $RENDER_ARGS -o single.exr --quiet || fail "single render failed"
if [ -s image.exr ] && "$VKPATH" compare image.exr single.exr >compare.txt 2>&1; then
  pass "phase 2 merged image vs single render: $(head -1 compare.txt)"
else
  fail "phase 2 merged image vs single render: $(head -1 compare.txt 2>/dev/null)"
fi

# ---------------------------------------------------------------- summary
cd "$work"
echo
if [ ${#failures[@]} = 0 ]; then
  echo "slurm-test: PASS (work dir $work)"
  exit 0
fi
echo "slurm-test: FAIL, ${#failures[@]} problem(s) (work dir $work):"
printf '  - %s\n' "${failures[@]}"
exit 1
