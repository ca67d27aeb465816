#!/usr/bin/env bash
# The Slurm scripts against a real single-node Slurm (Debian's slurm-wlm and munge): starts munged,
# slurmctld and slurmd on this machine, on loopback only, with a configuration of its own in a
# temporary folder; submits a small sweep as 4 array tasks and the dependent merge
# (scripts/slurm/submit.sh); and checks that the merged files are byte for byte what one
# unsharded run writes. Stops the daemons it started. Needs root (the daemons) and the release
# build; installs slurm-wlm and munge when missing.
#
#   scripts/slurm_check.sh
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "$(id -u)" -ne 0 ]; then
  echo "slurm_check: needs root to start munged, slurmctld and slurmd" >&2
  exit 2
fi
missing=()
for p in slurm-wlm munge; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "slurm_check: installing ${missing[*]}"
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >/dev/null
fi
[ -x build/release/testbed ] || cmake --build --preset release --target testbed

work=$(mktemp -d /tmp/puppet-slurm.XXXXXX)
pids=()
cleanup() {
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
  # munged forks into the background: its pid is in its pid file
  if [ -f "$work/munge/munged.pid" ]; then kill "$(cat "$work/munge/munged.pid")" 2>/dev/null || true; fi
  wait 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT

# munge: a key of our own, its socket in our folder
mkdir -p "$work/munge" "$work/state" "$work/spool"
dd if=/dev/urandom of="$work/munge/munge.key" bs=1024 count=1 status=none
chmod 0700 "$work/munge"
chmod 0400 "$work/munge/munge.key"
chown -R munge:munge "$work/munge" 2>/dev/null || true
socket="$work/munge/munge.socket"
munged --key-file="$work/munge/munge.key" --socket="$socket" \
  --pid-file="$work/munge/munged.pid" --log-file="$work/munge/munged.log" \
  --seed-file="$work/munge/munged.seed" --force 2>"$work/munged.err"
cpus=$(nproc)
cat >"$work/slurm.conf" <<CONF
ClusterName=puppet
SlurmctldHost=localhost(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$socket
CredType=cred/munge
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
SlurmctldPort=16817
SlurmdPort=16818
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
ReturnToService=2
NodeName=localhost NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=check Nodes=localhost Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$work/slurm.conf"
slurmctld -D -f "$SLURM_CONF" >"$work/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" -N localhost >"$work/slurmd.out" 2>&1 &
pids+=($!)
for _ in $(seq 60); do
  if sinfo -h -o %T 2>/dev/null | grep -qE '^(idle|mixed|allocated)'; then break; fi
  sleep 1
done
if ! sinfo -h -o %T | grep -qE '^(idle|mixed|allocated)'; then
  echo "slurm_check: the node did not come up:" >&2
  tail -5 "$work/slurmctld.log" "$work/slurmd.log" >&2 || true
  exit 1
fi
echo "slurm_check: $(sinfo -h -o '%P %D node, %c CPUs, %T') (Slurm $(sinfo -V | cut -d' ' -f2))"

flags=(--model chain:4 --scenario hang,yank --solver procedural,bullet-rigid --rule xpbd,relaxed
  --dt 1/60,1/120 --starts 6 --duration 0.5)
build/release/testbed robustness "${flags[@]}" --out "$work/unsharded" >/dev/null 2>&1
scripts/slurm/submit.sh "$work/slurm" 4 "${flags[@]}"
for _ in $(seq 300); do
  [ -z "$(squeue -h 2>/dev/null)" ] && break
  sleep 1
done
if [ -n "$(squeue -h)" ]; then
  echo "slurm_check: jobs still queued after 5 minutes:" >&2
  squeue >&2
  exit 1
fi
for f in robustness.csv robustness_summary.csv worst.csv; do
  if ! cmp -s "$work/unsharded/$f" "$work/slurm/merged/$f"; then
    echo "slurm_check: $f from the Slurm array differs from the unsharded run's" >&2
    ls -l "$work/slurm" "$work/slurm/merged" >&2 || true
    cat "$work"/slurm/slurm-*.out >&2 || true
    exit 1
  fi
done
echo "slurm_check: 4 array tasks and the dependent merge wrote the unsharded run's bytes"
