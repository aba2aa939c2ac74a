#!/usr/bin/env bash
# sweep_slurm.sh FLITTER SCRIPT: a private single-node Slurm (slurmctld +
# slurmd on 127.0.0.1, Debian 12's slurm-wlm 22.05, AuthType=auth/none so
# no munged, every file inside a temporary directory, unprivileged random
# ports) runs the job array that `flitter sweep --slurm` writes (2 strengths
# x 2 runs = 4 tasks) with `sbatch --wait`; `flitter sweep --collect` of it
# equals, wall times left out, that of the same sweep run by GNU parallel
# (-j2), and every job's final.state is byte-identical. The daemons are
# stopped on every exit path and nothing is left running.
set -uo pipefail
flitter=$1 script=$2
# the daemons live in /usr/sbin, which a user's PATH may lack
PATH=$PATH:/usr/sbin
for p in slurmctld slurmd sbatch sinfo squeue scancel; do
    command -v "$p" >/dev/null ||
        { echo "$p not installed (Debian package slurm-wlm): skipped"; exit 77; }
done
command -v parallel >/dev/null || { echo "GNU parallel not installed: skipped"; exit 77; }
# the job steps run the absolute paths the batch script names
case $flitter in /*) ;; *) flitter=$PWD/$flitter ;; esac
case $script in /*) ;; *) script=$PWD/$script ;; esac

dir=$(mktemp -d) || exit 2
chmod 755 "$dir"
ctl_pid= d_pid=
fail() { echo "FAIL: $*" >&2; exit 1; }
show_logs() { for f in "$dir"/log/*; do echo "--- $f" >&2; tail -n 30 "$f" >&2; done; }
# stop: cancel what is left, TERM both daemons, KILL after 10 s, reap them
stop() {
    [ -n "$ctl_pid" ] && scancel --quiet --full --user="$(id -un)" >/dev/null 2>&1
    for pid in $d_pid $ctl_pid; do kill -TERM "$pid" 2>/dev/null; done
    for pid in $d_pid $ctl_pid; do
        for _ in $(seq 100); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
        kill -KILL "$pid" 2>/dev/null
        wait "$pid" 2>/dev/null
    done
    ctl_pid= d_pid=
}
trap 'stop; rm -rf "$dir"' EXIT
trap 'exit 129' HUP; trap 'exit 130' INT; trap 'exit 143' TERM

mkdir -p "$dir/state" "$dir/spool" "$dir/log" "$dir/tmp" || exit 2
export SLURM_CONF=$dir/slurm.conf
node=flitternode
# slurmctld must find its own (short) host name in SlurmctldHost
host=$(hostname -s)
user=$(id -un)
cpus=$(nproc)

# start: write slurm.conf with ports $1 and $1+1, start both daemons in the
# foreground (-D, so their pids are ours to stop), wait up to 20 s for the
# node to be idle; returns 1 (daemons stopped) if it does not get there
start() {
    cat >"$SLURM_CONF" <<EOF
ClusterName=flittertest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$1
SlurmdPort=$(($1 + 1))
AuthType=auth/none
CredType=cred/none
SlurmUser=$user
SlurmdUser=$user
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
TmpFS=$dir/tmp
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SwitchType=switch/none
MpiDefault=none
MailProg=/bin/true
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
SlurmdParameters=config_overrides
NodeName=$node NodeAddr=127.0.0.1 NodeHostname=$node CPUs=$cpus State=UNKNOWN
PartitionName=test Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
    slurmctld -D -i -f "$SLURM_CONF" >"$dir/log/slurmctld.out" 2>&1 &
    ctl_pid=$!
    slurmd -D -N "$node" -f "$SLURM_CONF" >"$dir/log/slurmd.out" 2>&1 &
    d_pid=$!
    for _ in $(seq 40); do
        [ "$(sinfo -h -n "$node" -o %t 2>/dev/null)" = idle ] && return 0
        kill -0 "$ctl_pid" 2>/dev/null && kill -0 "$d_pid" 2>/dev/null || break
        sleep 0.5
    done
    stop
    return 1
}
# ports: random in 20000-59998; a second and third try if they were taken
started=
for _ in 1 2 3; do
    if start $((20000 + RANDOM % 39999)); then started=1; break; fi
done
if [ -z "$started" ]; then
    # slurmd needs cgroups mounted even with proctrack/linuxproc: in a
    # container or chroot without /sys/fs/cgroup there is no Slurm to test
    if grep -qs 'Unable to initialize cgroup plugin' "$dir/log/slurmd.log" "$dir/log/slurmd.out"; then
        echo "slurmd cannot start without cgroups (/sys/fs/cgroup not mounted): skipped"
        exit 77
    fi
    show_logs; fail "Slurm did not start (node never idle)"
fi

# the sweep through Slurm
"$flitter" sweep "$script" -D strength=50,200 --runs 2 --frames 20 --out "$dir/slurm" --slurm \
    >/dev/null || fail "--slurm exited $?"
grep -qx '#SBATCH --array=0-3' "$dir/slurm/sweep.sbatch" || fail "array line"
(cd "$dir" && timeout 90 sbatch --wait --quiet "$dir/slurm/sweep.sbatch") >"$dir/sbatch.out" 2>&1 ||
    { cat "$dir/sbatch.out" >&2; show_logs; fail "sbatch --wait exited $?"; }
[ "$(ls "$dir"/slurm/slurm-*_*.out | wc -l)" -eq 4 ] || { ls "$dir/slurm" >&2; fail "not 4 array tasks' outputs"; }
# completing jobs leave the queue within seconds
for _ in $(seq 50); do [ -z "$(squeue -h 2>&1)" ] && break; sleep 0.2; done
[ -z "$(squeue -h 2>&1)" ] || { squeue >&2; fail "jobs still queued after sbatch --wait"; }
stop

# the same sweep through GNU parallel
"$flitter" sweep "$script" -D strength=50,200 --runs 2 --frames 20 --out "$dir/par" \
    >"$dir/jobs" || fail "sweep listing exited $?"
parallel --will-cite -j2 <"$dir/jobs" || fail "parallel exited $?"

"$flitter" sweep --collect "$dir/slurm" >"$dir/slurm.csv" || fail "collect (slurm) exited $?"
"$flitter" sweep --collect "$dir/par" >"$dir/par.csv" || fail "collect (parallel) exited $?"
cat >"$dir/want.csv" <<'CSV'
job,strength,run,seed,exit
0,50,0,0,0
1,50,1,1,0
2,200,0,0,0
3,200,1,1,0
CSV
cut -d, -f1-5 "$dir/slurm.csv" | diff -u "$dir/want.csv" - >&2 || fail "Slurm's collected CSV"
diff -u <(cut -d, -f1-5 "$dir/par.csv") <(cut -d, -f1-5 "$dir/slurm.csv") >&2 ||
    fail "Slurm's CSV differs from parallel's"
head -1 "$dir/slurm.csv" | grep -qx 'job,strength,run,seed,exit,wall_seconds' || fail "CSV header"
for j in 0000 0001 0002 0003; do
    [ -s "$dir/slurm/job-$j/final.state" ] || fail "job $j: no final.state"
    cmp -s "$dir/par/job-$j/final.state" "$dir/slurm/job-$j/final.state" ||
        fail "job $j: final.state differs between Slurm and parallel"
done
echo "sweep_slurm: all checks passed"
