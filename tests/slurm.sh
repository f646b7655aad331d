#!/bin/sh
# The sweep layout as a SLURM job array, on a real single-node cluster
# that the test starts and stops: slurmctld and slurmd from Debian's
# slurm-wlm, own configuration, state and ports in a temporary directory,
# auth/none (no munge daemon).  The copied slurm.sbatch runs a grid; the
# array is cancelled half way and resumed with sweep-missing; the reduced
# table equals the one GNU parallel makes of the same grid.
. "$(dirname "$0")/lib.sh"
top=$(cd "$(dirname "$0")/.." && pwd)
PATH=$top/studies/sweep:$PATH:/usr/sbin:/sbin

for p in slurmctld slurmd sbatch squeue scancel sinfo parallel; do
	command -v $p >/dev/null 2>&1 || skip_all "$p not installed (Debian slurm-wlm, parallel)"
done
[ "$(id -u)" -eq 0 ] || skip_all "slurmd must run as root to start jobs"

# Two free TCP ports: nothing listening on them in /proc/net/tcp.
used() { awk -v p="$(printf '%04X' "$1")" 'NR > 1 { split($2, a, ":"); if (a[2] == p) f = 1 } END { exit !f }' \
	/proc/net/tcp /proc/net/tcp6 2>/dev/null; }
port=$((30000 + $$ % 10000 * 2))
while used $port || used $((port + 1)); do port=$((port + 2)); done

S=$T/slurm
mkdir -p "$S/state" "$S/spool" "$S/log"
H=$(hostname -s)
cat >"$S/slurm.conf" <<CONF
ClusterName=tistest
SlurmctldHost=$H(127.0.0.1)
SlurmctldPort=$port
SlurmdPort=$((port + 1))
AuthType=auth/none
CredType=cred/none
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$S/state
SlurmdSpoolDir=$S/spool
SlurmctldPidFile=$S/slurmctld.pid
SlurmdPidFile=$S/slurmd.pid
SlurmctldLogFile=$S/log/slurmctld.log
SlurmdLogFile=$S/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
ReturnToService=2
NodeName=tisnode NodeHostname=$H NodeAddr=127.0.0.1 CPUs=2 State=UNKNOWN
PartitionName=tis Nodes=tisnode Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$S/slurm.conf
ctld= slurmd=
stop() {
	[ -n "$slurmd" ] && kill "$slurmd" 2>/dev/null
	[ -n "$ctld" ] && kill "$ctld" 2>/dev/null
	[ -n "$slurmd$ctld" ] && wait $slurmd $ctld 2>/dev/null
}
at_exit stop
slurmctld -D >"$S/log/ctld.out" 2>&1 &
ctld=$!
slurmd -D -N tisnode >"$S/log/slurmd.out" 2>&1 &
slurmd=$!
i=0
until [ "$(sinfo -h -n tisnode -o %t 2>/dev/null)" = idle ] || [ $i -ge 300 ]; do
	sleep 0.1
	i=$((i + 1))
done
if [ $i -ge 300 ]; then
	why=$(cat "$S/log/"*.log "$S/log/"*.out 2>/dev/null | grep -i -m1 -E 'error|fatal' || echo "node not idle after 30 s")
	skip_all "no single-node SLURM here: $why"
fi
plan 9

# wait_job ID: until no task of the job is pending or running (at most 120 s)
wait_job() {
	k=0
	while [ -n "$(squeue -h -j "$1" 2>/dev/null)" ] && [ $k -lt 1200 ]; do sleep 0.1; k=$((k + 1)); done
	[ $k -lt 1200 ]
}

D=$T/sweep
mkdir -p "$D"
{ printf 'x\ty\n'; for i in 1 2 3 4 5 6; do printf '%s\t%s\n' "$i" "$((i * i))"; done; } >"$D/params.tsv"
# rows 1-3 at once; rows 4-6 wait for the file "go" (at most 60 s)
cat >"$D/job" <<'JOB'
#!/bin/sh
echo "$ROW ${SLURM_ARRAY_TASK_ID:-none}" >>runs.log
if [ "$ROW" -gt 3 ]; then
	i=0
	while [ ! -e go ] && [ $i -lt 600 ]; do sleep 0.1; i=$((i + 1)); done
fi
printf 'sum\n%s\n' "$((x + y))"
JOB
chmod +x "$D/job"
cp "$top/studies/sweep/slurm.sbatch" "$T/my.sbatch"

job=$(sbatch --parsable --array=1-"$(sweep-count "$D")" --export=ALL,SWEEP_DIR="$D" \
	--chdir="$T" --output="$T/slurm-%A_%a.out" "$T/my.sbatch")
ok "sbatch accepted the array (job $job)" test -n "$job"
i=0
until [ -s "$D/results/3.tsv" ] && [ -s "$D/results/2.tsv" ] && [ -s "$D/results/1.tsv" ] &&
	[ "$(grep -c . "$D/runs.log" 2>/dev/null)" -ge 5 ] || [ $i -ge 600 ]; do
	sleep 0.1
	i=$((i + 1))
done
ok "rows 1-3 done, two of rows 4-6 running" test $i -lt 600
scancel "$job"
ok "scancel ends the array" wait_job "$job"
ok "after the cancel: rows 4-6 missing" test "$(sweep-missing "$D")" = 4-6
ok "every task ran its own row" awk '$1 != $2 { exit 1 }' "$D/runs.log"
touch "$D/go"
: >"$D/runs.log"
job2=$(sbatch --parsable --array="$(sweep-missing "$D")" --export=ALL,SWEEP_DIR="$D" \
	--chdir="$T" --output="$T/slurm-%A_%a.out" "$T/my.sbatch")
ok "the resubmitted missing rows finish" wait_job "$job2"
ok "resumed: every row done, only rows 4-6 ran again" sh -c \
	"test -z \"\$(sweep-missing '$D')\" && test \"\$(cut -d' ' -f1 '$D/runs.log' | sort -n | tr '\n' ' ')\" = '4 5 6 '"

# The same grid under GNU parallel gives the same table.
P=$T/par
mkdir -p "$P"
cp "$D/params.tsv" "$D/job" "$P/"
touch "$P/go"
parallel.sh "$P" -j2
sweep-reduce "$D" | grep -v '^#' >"$T/slurm.tsv"
sweep-reduce "$P" | grep -v '^#' >"$T/par.tsv"
ok "the reduced table: x + y for each row" awk -F'\t' 'NR > 1 && $3 != $1 + $2 { bad = 1 } END { exit bad || NR != 7 }' "$T/slurm.tsv"
ok "SLURM and GNU parallel reduce to the same table" cmp -s "$T/slurm.tsv" "$T/par.tsv"
done_testing
