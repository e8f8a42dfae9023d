#!/usr/bin/env bash
# A real Slurm run on this machine: starts munged, slurmctld and slurmd in a temporary folder (a
# generated slurm.conf for this host with the CPUs and memory `slurmd -C` finds), submits the
# README's array job (examples/slurm/render-array.sh) and checks:
#   1. `sbatch --array=0-3` renders frames 0-15 of `room` at 160x120 with --shard I/4 into one
#      folder: the folder holds exactly the 16 frames, each equal (cmp) to a local render;
#   2. resume: the same array into a second folder, task 3 cancelled (scancel) after its first
#      frame; its finished frames stay, nothing half-written is left; rerun as the README says
#      (sbatch --array=3, the same script, so --skip-existing), it renders only the missing
#      frames (the others keep their inode and mtime) and every frame equals the local render.
# Usage: scripts/slurm-test.sh [BUILD_DIR]   (default ./build; needs BUILD_DIR/bin/relief)
# Exit: 0 pass, 1 fail, 77 skipped (Slurm or munge not installed, or the daemons cannot start:
# the message says why). Everything it starts is killed on exit, pass or fail (trap).
# KEEP=1 keeps the temporary folder (logs, slurm.conf, frames) and prints its path.
set -euo pipefail
src="$(cd "$(dirname "$0")/.." && pwd)"
build="$(cd "${1:-$src/build}" && pwd)"
relief="$build/bin/relief"
job_script="$src/examples/slurm/render-array.sh"
export PATH="$PATH:/usr/sbin:/sbin"
t0=$SECONDS

say() { echo "slurm-test: $*"; }
skip() { echo "slurm-test: SKIPPED: $*" >&2; exit 77; }
fail() { echo "slurm-test: FAIL: $*" >&2; exit 1; }

# The README shows the job script this test submits, verbatim.
readme="$(cat "$src/README.md")"
[[ "$readme" == *"$(cat "$job_script")"* ]] ||
  fail "README.md does not show examples/slurm/render-array.sh verbatim (the job this test runs)"
[ -x "$relief" ] || fail "$relief: not built (cmake --build $build --target relief)"
for tool in munged mungekey slurmctld slurmd sbatch squeue scancel scontrol sinfo; do
  command -v "$tool" > /dev/null ||
    skip "$tool not installed (Debian: slurmctld slurmd slurm-client munge; scripts/install-deps.sh)"
done
# (the help read whole first: `| grep -q` exits at the first match, and under pipefail the
# SIGPIPE of the help's later writes would fail the pipe)
render_help="$("$relief" render --help)"
[[ "$render_help" == *--skip-existing* ]] ||
  fail "$relief render has no --skip-existing (the job script's resume needs it)"

work="$(mktemp -d /tmp/relief-slurm.XXXXXX)"
chmod 700 "$work"
mkdir -p "$work"/{munge,state,spool,log,ref,out,resume}
pids=()
cleanup() {
  local rc=$?
  set +e
  # Jobs still running (a failure or a signal mid-test) on our cluster only: cancelled while it is
  # up, since their steps outlive slurmd.
  if [ "${SLURM_CONF:-}" = "$work/slurm.conf" ] && [ -n "$(squeue -h -o %i 2> /dev/null)" ]; then
    scancel --user="$(id -un)" 2> /dev/null
    for _ in $(seq 50); do [ -z "$(squeue -h -o %i 2> /dev/null)" ] && break; sleep 0.1; done
  fi
  # Children of this shell, stopped in reverse order: slurmd (it kills the job steps it runs),
  # the controller, munged; each waited for (reaped), SIGKILL after 5 s.
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do
    pid=${pids[i]}
    kill "$pid" 2> /dev/null
    for _ in $(seq 50); do
      [ -e "/proc/$pid" ] && [ "$(cut -d' ' -f3 "/proc/$pid/stat" 2> /dev/null)" != Z ] || break
      sleep 0.1
    done
    kill -9 "$pid" 2> /dev/null
    wait "$pid" 2> /dev/null
  done
  if [ "$rc" -ne 0 ] && [ "$rc" -ne 77 ]; then
    for f in "$work"/log/*; do [ -f "$f" ] && { echo "--- $f (tail)"; tail -n 15 "$f"; }; done
  fi
  if [ "${KEEP:-0}" = 1 ]; then say "kept $work"; else rm -rf "$work"; fi
  exit "$rc"
}
trap cleanup EXIT
trap 'exit 1' INT TERM

# --- munge: a key of our own and a socket in the temporary folder.
mungekey --create --keyfile="$work/munge/munge.key" > "$work/log/mungekey.log" 2>&1 ||
  { cat "$work/log/mungekey.log" >&2; skip "mungekey could not create a key (above)"; }
sock="$work/munge/munge.socket.2"
munged --foreground --force --socket="$sock" --key-file="$work/munge/munge.key" \
  --pid-file="$work/munge/munged.pid" --log-file="$work/log/munged.log" \
  --seed-file="$work/munge/munged.seed" > "$work/log/munged.out" 2>&1 &
pids+=($!)
for _ in $(seq 50); do
  [ -S "$sock" ] && break
  kill -0 "${pids[0]}" 2> /dev/null || break
  sleep 0.1
done
[ -S "$sock" ] ||
  { cat "$work/log/munged.out" "$work/log/munged.log" 2> /dev/null; skip "munged does not start"; }

# --- slurm.conf for this host: two free TCP ports on loopback, the node as slurmd -C sees it.
free_port() {
  local p
  while :; do
    p=$((20000 + RANDOM % 30000))
    if ! (exec 3<> "/dev/tcp/127.0.0.1/$p") 2> /dev/null; then echo "$p"; return; fi
  done
}
ctld_port=$(free_port)
slurmd_port=$(free_port)
[ "$slurmd_port" != "$ctld_port" ] || slurmd_port=$((ctld_port + 1))
host="$(hostname -s)"
node_line="$(slurmd -C 2> /dev/null | head -n 1)"
[[ "$node_line" == NodeName=* ]] || skip "slurmd -C does not describe this machine: $node_line"
node_line="${node_line/#NodeName=* CPUs=/NodeName=$host CPUs=}"
user="$(id -un)"
conf="$work/slurm.conf"
cat > "$conf" << EOF
ClusterName=relieftest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
AuthInfo=socket=$sock
CredType=cred/munge
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
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/builtin
MpiDefault=none
SwitchType=switch/none
MailProg=/bin/true
ReturnToService=2
KillWait=5
MinJobAge=600
$node_line NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=relief Nodes=$host Default=YES MaxTime=10 State=UP
EOF
export SLURM_CONF="$conf"

slurmctld -D -c -f "$conf" > "$work/log/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -N "$host" -f "$conf" > "$work/log/slurmd.out" 2>&1 &
pids+=($!)
up=0
for _ in $(seq 100); do
  state="$(sinfo -h -N -o %T 2> /dev/null || true)"
  if [ "$state" = idle ]; then up=1; break; fi
  for pid in "${pids[@]}"; do kill -0 "$pid" 2> /dev/null || break 2; done
  sleep 0.2
done
if [ "$up" != 1 ]; then
  for f in "$work"/log/slurm*; do echo "--- $f"; tail -n 10 "$f"; done >&2
  skip "the Slurm daemons did not bring the node up in 20 s (node state: '${state:-none}'; logs above)"
fi
say "cluster up in $((SECONDS - t0)) s: $(sinfo -h -N -o '%N %c CPUs %m MB %T')"

# The jobs find `relief` on PATH, as on a farm where it is installed (sbatch exports PATH).
export PATH="$build/bin:$PATH"

# --- the reference: the same 16 frames rendered here, in one process.
scene=room frames=0-15 size=160x120
"$relief" render "$scene" --frames "$frames" --size "$size" -o "$work/ref/f_%04d.png" \
  > "$work/log/ref.log" 2>&1 || { cat "$work/log/ref.log"; fail "local reference render failed"; }
expected=()
for f in $(seq 0 15); do expected+=("$(printf 'f_%04d.png' "$f")"); done

# Checks that folder $1 holds exactly the 16 frames and each equals the reference.
check_frames() {
  local dir=$1 got want
  got="$(cd "$dir" && ls -A | sort)"
  want="$(printf '%s\n' "${expected[@]}" | sort)"
  [ "$got" = "$want" ] || fail "$dir holds [$(echo $got)], expected exactly f_0000.png..f_0015.png"
  for name in "${expected[@]}"; do
    cmp -s "$dir/$name" "$work/ref/$name" || fail "$dir/$name differs from the local render"
  done
}
# Waits until job $1 (all its array tasks) has left the queue.
wait_job() {
  for _ in $(seq 600); do
    [ -z "$(squeue -h -j "$1" -o %i 2> /dev/null)" ] && return 0
    sleep 0.2
  done
  fail "job $1 still queued after 120 s: $(squeue -h -j "$1" -o '%i %T %r')"
}
task_state() { scontrol -o show job "$1" | grep -o 'JobState=[A-Z_]*' | cut -d= -f2; }
submit() {  # submit OUT_DIR ARRAY: the README's job, one shard of 4 a task
  sbatch --parsable --array="$2" --chdir="$work" --output="$work/log/$(basename "$1")-%A_%a.log" \
    "$job_script" "$scene" "$frames" 4 "$1/f_%04d.png" --size "$size"
}

# --- 1. the array job: 4 tasks, 4 frames each, one folder.
job=$(submit "$work/out" 0-3) || fail "sbatch refused the array job"
wait_job "$job"
for i in 0 1 2 3; do
  s="$(task_state "${job}_$i")"
  [ "$s" = COMPLETED ] || fail "array task ${job}_$i ended $s (log: $(cat "$work"/log/out-*_"$i".log))"
done
check_frames "$work/out"
say "array job $job: 4 tasks COMPLETED, 16 frames, each equal to the local render (cmp)"

# --- 2. resume: task 3 (frames 12-15) cancelled after its first frame, then rerun.
job=$(submit "$work/resume" 0-3) || fail "sbatch refused the array job"
for _ in $(seq 1200); do
  [ -e "$work/resume/f_0012.png" ] && break
  [ -z "$(squeue -h -j "$job" -o %i)" ] && break
  sleep 0.05
done
scancel "${job}_3"
wait_job "$job"
s="$(task_state "${job}_3")"
[ "$s" = CANCELLED ] || fail "task ${job}_3 ended $s before scancel reached it (frames too fast?)"
for i in 0 1 2; do
  s="$(task_state "${job}_$i")"
  [ "$s" = COMPLETED ] || fail "array task ${job}_$i ended $s"
done
# What task 3 left: only whole frames of its own (12-15), no temporary, at least one, not all.
# shellcheck disable=SC2010  # any name there is either a frame or a stray to report
left="$(cd "$work/resume" && ls -A | grep -v '^f_00\(0[0-9]\|1[01]\)\.png$' || true)"
stray="$(printf '%s\n' "$left" | grep -v '^f_001[2-5]\.png$' | grep . || true)"
[ -z "$stray" ] || fail "the cancelled task left [$(echo $stray)] behind"
n_left=$(printf '%s\n' "$left" | grep -c . || true)
[ "$n_left" -ge 1 ] && [ "$n_left" -lt 4 ] ||
  fail "cancelled task 3 left $n_left of its 4 frames (expected 1 to 3)"
declare -A before
for name in $left; do before[$name]="$(stat -c '%i %Y.%y' "$work/resume/$name")"; done
job2=$(submit "$work/resume" 3) || fail "sbatch refused the rerun"
wait_job "$job2"
s="$(task_state "${job2}_3")"
[ "$s" = COMPLETED ] || fail "rerun ${job2}_3 ended $s"
for name in $left; do
  [ "$(stat -c '%i %Y.%y' "$work/resume/$name")" = "${before[$name]}" ] ||
    fail "the rerun rewrote $name, which the cancelled task had finished"
done
check_frames "$work/resume"
say "resume: task ${job}_3 CANCELLED after $n_left of 4 frames; rerun ${job2}_3 rendered the other" \
  "$((4 - n_left)), kept the finished ones untouched; all 16 equal the local render"
say "PASS in $((SECONDS - t0)) s"
