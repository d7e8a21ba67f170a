#!/usr/bin/env bash
# A study's Slurm job array through a real, private, one-node Slurm cluster (make slurm-check):
#   1. starts munged with its own key and socket, slurmctld and slurmd with their own
#      configuration, ports and state folders, all under DIR (nothing in /etc or /run is
#      used or changed, so it does not meet another cluster or another run of this check);
#   2. writes the column study's job array (tools/study.py --slurm), submits it with
#      `sbatch --wait` and collects it (--collect);
#   3. checks that every task ran and that each case's settlement is gamma H^2 / (2M)
#      (1e-9), then stops the daemons (also when something fails).
# Needs the Debian packages slurmctld, slurmd, slurm-client and munge (make slurm-check
# installs them), and root or a user that may run the daemons.
#
#   tools/slurm_cluster_check.sh CFRD DIR
# Prints PASS/FAIL lines; exit status 1 if a check failed.
set -uo pipefail
cfrd=$(realpath "$1")
dir=$(realpath -m "$2")
rm -rf "$dir"
mkdir -p "$dir"/munge "$dir"/state "$dir"/spool "$dir"/log
chmod 700 "$dir"/munge
pids=()
cleanup() {
    for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null; done
    for pid in "${pids[@]}"; do wait "$pid" 2>/dev/null; done
}
trap cleanup EXIT
fail() { echo "FAIL slurm-cluster/$1"; exit 1; }

# Free TCP ports for slurmctld and slurmd: ask the kernel for two.
read -r ctld_port slurmd_port < <(python3 -c '
import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(*(x.getsockname()[1] for x in s))')

head -c 1024 /dev/urandom >"$dir"/munge/munge.key
chmod 600 "$dir"/munge/munge.key
munged --foreground --force --key-file="$dir"/munge/munge.key \
    --socket="$dir"/munge/socket --pid-file="$dir"/munge/pid \
    --log-file="$dir"/log/munged.log --seed-file="$dir"/munge/seed >"$dir"/log/munged.out 2>&1 &
pids+=($!)

host=$(hostname -s)
cpus=$(nproc)
user=$(id -un)
cat >"$dir"/slurm.conf <<EOF
ClusterName=cfrdcheck
SlurmctldHost=$host
SlurmUser=$user
SlurmdUser=$user
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
AuthType=auth/munge
AuthInfo=socket=$dir/munge/socket
CredType=cred/munge
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
ReturnToService=2
NodeName=$host CPUs=$cpus State=UNKNOWN
PartitionName=check Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF=$dir/slurm.conf
for i in $(seq 50); do [[ -S $dir/munge/socket ]] && break; sleep 0.1; done
[[ -S $dir/munge/socket ]] || fail "munged: no socket ($(tail -3 "$dir"/log/munged.log))"
slurmctld -D -i >"$dir"/log/slurmctld.out 2>&1 &
pids+=($!)
slurmd -D >"$dir"/log/slurmd.out 2>&1 &
pids+=($!)
state=""
for i in $(seq 100); do
    state=$(sinfo -h -N -o %T 2>/dev/null | head -1)
    [[ $state == idle ]] && break
    sleep 0.2
done
[[ $state == idle ]] ||
    fail "the node did not come up (state '$state'): $(tail -3 "$dir"/log/slurmctld.log)"
echo "PASS slurm-cluster/up: one-node cluster $host ($cpus CPUs) on ports $ctld_port, $slurmd_port"

study=$dir/study
python3 tools/study.py test/study/column.dat --dir "$study" --cfrd "$cfrd" --slurm \
    --sbatch=--time=00:05:00 >"$dir"/log/study.out 2>&1 ||
    fail "study --slurm: $(cat "$dir"/log/study.out)"
timeout 300 sbatch --wait "$study"/study.slurm >"$dir"/log/sbatch.out 2>&1
status=$?
job=$(sed -n 's/^Submitted batch job //p' "$dir"/log/sbatch.out)
tasks=$(ls "$study"/results/slurm-*_*.out 2>/dev/null | wc -l)
if [[ $status -eq 0 && $tasks -eq 4 ]]; then
    echo "PASS slurm-cluster/array: job $job, 4 array tasks ran (sbatch --wait exit 0)"
else
    fail "array: sbatch --wait exit $status, $tasks task outputs: $(cat "$dir"/log/sbatch.out)"
fi
python3 tools/study.py test/study/column.dat --dir "$study" --collect \
    >"$dir"/log/collect.out 2>&1 ||
    fail "collect: $(cat "$dir"/log/collect.out)"
python3 - "$study"/study-results.csv <<'PY'
import csv, sys
worst = 0.0
rows = list(csv.DictReader(open(sys.argv[1])))
for r in rows:
    e, nu = float(r["E"]), float(r["NU"])
    m = e * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
    exact = 20.0 * 10.0 ** 2 / (2 * m)
    worst = max(worst, abs(float(r["max_settlement_m"]) - exact) / exact
                if r["status"] == "ok" else float("inf"))
ok = len(rows) == 4 and worst <= 1e-9
print(f"{'PASS' if ok else 'FAIL'} slurm-cluster/results: 4 cases collected, max rel. error "
      f"against gamma H^2/(2M) {worst:.1e} (tol 1e-9)")
sys.exit(0 if ok else 1)
PY
