#!/usr/bin/env bash
# Runs the Slurm job array recipe of docs/batch.md for real, on a one-node Slurm started on
# this machine, and checks what it leaves against a sequential `eulervop batch --jobs 1`.
#
#   tools/slurm_cluster_test.sh [path/to/eulervop]      (as root; opt-in: `ctest -L cluster`)
#
# Default program: $EULERVOP_BUILD_DIR/eulervop, else build/eulervop. Installs the Debian packages
# slurm-wlm and munge (and jq, to read the manifests) if missing. Everything else lives in a
# private temp directory: munged runs with its own key and socket, slurmctld and slurmd with a
# slurm.conf given by -f and SLURM_CONF, so nothing in /etc is written and no systemd is needed.
# The daemons talk over the loopback only and are stopped on exit, failure included. The job
# script is docs/batch.md's ```bash block as written, so a change to that page is what gets tested.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
prog=${1:-${EULERVOP_BUILD_DIR:-$root/build}/eulervop}
[[ -x $prog ]] || { echo "FAIL: no program at $prog (build it first)"; exit 1; }
prog=$(cd "$(dirname "$prog")" && pwd)/$(basename "$prog")
timeout_s=${SLURM_TEST_TIMEOUT:-1200}
export LC_ALL=C  # `batch --shard` sorts the scene paths bytewise; so must the checks

if ! command -v slurmctld > /dev/null || ! command -v munged > /dev/null || ! command -v jq > /dev/null; then
  [[ $(id -u) == 0 ]] || { echo "FAIL: slurm-wlm, munge or jq is missing and installing needs root"; exit 1; }
  { apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y slurm-wlm munge jq; } > /dev/null 2>&1 ||
    { echo "FAIL: could not install slurm-wlm, munge and jq with apt-get"; exit 1; }
fi

tmp=$(mktemp -d /tmp/eulervop-slurm.XXXXXX)
alive() { [[ $(ps -o stat= -p "$1" 2> /dev/null) == [^Z]* ]]; }
stop() {
  set +e
  # Tasks left (a timeout) are cancelled first, so that no slurmstepd outlives its slurmd.
  if [[ -n ${jobid:-} ]]; then
    scancel "$jobid" 2> /dev/null
    for _ in $(seq 30); do [[ -z $(squeue -h 2> /dev/null) ]] && break; sleep 1; done
  fi
  local d pid
  for d in slurmd slurmctld munged; do
    [[ -s $tmp/$d.pid ]] || continue
    pid=$(cat "$tmp/$d.pid")
    kill "$pid" 2> /dev/null
    for _ in $(seq 20); do alive "$pid" || break; sleep 0.5; done
    alive "$pid" && kill -9 "$pid"
  done
  [[ ${KEEP_TMP:-0} == 1 ]] && echo "kept $tmp" || rm -rf "$tmp"
}
trap stop EXIT
trap 'exit 143' INT TERM  # so that the EXIT trap stops the daemons then too
fail() { echo "FAIL: $*"; for l in "$tmp"/*.log; do echo "--- $l"; tail -n 15 "$l"; done; exit 1; }

# munged: a fresh key, socket and pid file of its own, so a system munged is neither used nor hit.
mkdir -p "$tmp"/munge && chmod 700 "$tmp"/munge
dd if=/dev/urandom of="$tmp"/munge/key bs=1024 count=1 status=none && chmod 400 "$tmp"/munge/key
munged --force --key-file="$tmp"/munge/key --socket="$tmp"/munge/socket --pid-file="$tmp"/munged.pid \
  --seed-file="$tmp"/munge/seed --log-file="$tmp"/munged.log || fail "munged did not start"

# One node, every daemon on the loopback, no cgroup and no accounting (absent in a container).
host=$(hostname -s)
mkdir -p "$tmp"/state "$tmp"/spool
cat > "$tmp"/slurm.conf << EOF
ClusterName=eulervop
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=16817
SlurmdPort=16818
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$tmp/munge/socket
CredType=cred/munge
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/slurmctld.pid
SlurmdPidFile=$tmp/slurmd.pid
SlurmctldLogFile=$tmp/slurmctld.log
SlurmdLogFile=$tmp/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
ReturnToService=2
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MinJobAge=3600
NodeName=$host NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF=$tmp/slurm.conf
slurmctld -f "$SLURM_CONF" || fail "slurmctld did not start"
slurmd -f "$SLURM_CONF" || fail "slurmd did not start"
for _ in $(seq 60); do sinfo -h -N -o %t 2> /dev/null | grep -qx idle && break; sleep 1; done
sinfo -h -N -o %t | grep -qx idle || fail "the node is not idle after 60 s: $(sinfo -h -N -o '%t %E' 2>&1)"

# The job script of docs/batch.md, the ```bash block after the line "A Slurm job array...".
job=$(awk '/^A Slurm job array/ { t = 1; next } t && /^```/ { if (b) exit; b = 1; next } b' "$root"/docs/batch.md)
shards=$(sed -n 's/^#SBATCH --array=1-\([0-9]*\)$/\1/p' <<< "$job")
[[ -n $shards ]] || fail "docs/batch.md: no job script with '#SBATCH --array=1-N' after 'A Slurm job array'"
work=$tmp/work
mkdir -p "$work"/data/scenes/hard
cp "$root"/data/scenes/hard/*.toml "$work"/data/scenes/hard/
printf '%s\n' "$job" > "$work"/job.sh
cd "$work"
echo "job script (from docs/batch.md):"; sed 's/^/  /' job.sh

"$prog" batch data/scenes/hard/*.toml --out-dir seq --jobs 1 2> seq.log || fail "sequential batch failed"

# The job gets this environment (and so the program's directory first on PATH) via --export=ALL.
export PATH=$(dirname "$prog"):$PATH
unset SBATCH_EXPORT SBATCH_ARRAY_INX
start=$SECONDS
set +e
timeout "$timeout_s" sbatch --wait --export=ALL --parsable job.sh > jobid 2> sbatch.err
rc=$?
set -e
jobid=$(cut -d';' -f1 < jobid)
[[ -n $jobid ]] || fail "sbatch did not submit the job: $(cat sbatch.err)"
[[ $rc == 124 ]] && fail "job array not done after $timeout_s s (cancelled)"
echo "job $jobid: sbatch --wait exited $rc after $((SECONDS - start)) s"

# Checks, each in a subshell (it may `exit 1`); any failing one makes the exit status non-zero.
bad=0
check() { if (eval "$2"); then echo "ok   $1"; else echo "FAIL $1"; bad=1; fi; }
scenes=$(ls data/scenes/hard/*.toml | xargs -n1 basename | sed 's/\.toml$//' | sort)
n=$(wc -l <<< "$scenes")
states=$(scontrol show job "$jobid" | grep -oE '(^| )(ArrayTaskId|JobState|ExitCode)=[^ ]+' | sed 's/^ //' |
  paste -d' ' - - - | sort -t= -k2 -n)
check "$shards array tasks ended COMPLETED with exit 0:0 (scontrol show job)" \
  '[[ $(grep -c "JobState=COMPLETED ExitCode=0:0" <<< "$states") == "$shards" ]]'
check "$shards slurm-${jobid}_*.out files" '[[ $(ls slurm-"${jobid}"_*.out | wc -l) == "$shards" ]]'
refs=$(cd out 2> /dev/null && find . -name reference.csv | sort || true)
check "$n scenes, one out/NAME/reference.csv each" \
  '[[ $(sed "s|^\./||; s|/reference.csv$||" <<< "$refs") == "$scenes" ]]'
check "every reference.csv byte for byte what batch --jobs 1 writes" \
  'for s in $scenes; do cmp -s out/$s/reference.csv seq/$s/reference.csv || exit 1; done'
check "$shards manifests out/manifest-I-of-$shards.json, each of its own shard" \
  'for i in $(seq "$shards"); do
     [[ $(jq -r .shard out/manifest-$i-of-$shards.json) == "$i/$shards" ]] || exit 1; done &&
   [[ $(ls out/manifest*.json | wc -l) == "$shards" ]]'
listed=$(jq -r '.scenes[].name' out/manifest-*-of-"$shards".json 2> /dev/null | sort || true)
check "the manifests list every scene exactly once" '[[ $listed == "$scenes" ]]'
check "every scene listed with status ok" \
  '[[ $(jq -r ".scenes[].status" out/manifest-*-of-"$shards".json | grep -cx ok) == "$n" ]]'
check "each manifest lists its own shard's scenes (none overwritten)" \
  'i=0; for s in $(ls data/scenes/hard/*.toml | sort); do i=$((i + 1));
     k=$(( (i - 1) % shards + 1 ));
     jq -e --arg p "$s" "[.scenes[].path] | index(\$p) != null" out/manifest-$k-of-$shards.json \
       > /dev/null || exit 1;
   done'
if [[ $bad != 0 ]]; then
  echo "task states:"; sed 's/^/  /' <<< "$states"
  echo "FAIL: the Slurm recipe of docs/batch.md did not do what it says"
  exit 1
fi
echo "PASS: the Slurm job array of docs/batch.md ($shards tasks, $n scenes) matches batch --jobs 1"
