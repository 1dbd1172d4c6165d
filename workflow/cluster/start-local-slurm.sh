#!/usr/bin/env bash
# A single-node SLURM on this Debian or Ubuntu machine, for the tests and CI (issue 34): the
# distribution's slurmctld, slurmd and munge, a munge key, a slurm.conf written from
# `slurmd -C`, the daemons started without systemd. Run as root. Idempotent: what runs is left
# running. Stop it with stop-local-slurm.sh (by PID, never by process name).
#
#   bash workflow/cluster/start-local-slurm.sh     # exit 0: up; 3: cannot start here (one line why)
#
# No accounting database (slurmdbd): sacct answers "accounting storage is disabled", so
# Snakemake's SLURM executor must ask squeue, as config/profiles/slurm does.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/local-slurm.sh"  # STATE, MARK
cannot() { echo "local SLURM not started: $*" >&2; exit 3; }
[ "$(id -u)" = 0 ] || cannot "not root (it installs packages and starts daemons)"
if ! command -v slurmctld >/dev/null || ! command -v slurmd >/dev/null || ! command -v munged >/dev/null \
        || ! command -v sbatch >/dev/null; then
    command -v apt-get >/dev/null || cannot "no apt-get to install slurmctld, slurmd and munge"
    DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends slurmctld slurmd slurm-client munge \
        > "/tmp/stonedem-slurm-apt.log" 2>&1 || cannot "apt-get install failed (/tmp/stonedem-slurm-apt.log)"
fi
mkdir -p "$STATE"/spool "$STATE"/ctld /etc/slurm /etc/munge /run/munge /var/log/munge /var/lib/munge

alive() { [ -s "$1" ] && kill -0 "$(cat "$1")" 2>/dev/null; }

# munge: a key once, then the daemon (its PID file is where stop-local-slurm.sh finds it)
if [ ! -s /etc/munge/munge.key ]; then
    dd if=/dev/urandom bs=1 count=1024 of=/etc/munge/munge.key status=none
fi
chown -R munge:munge /etc/munge /run/munge /var/log/munge /var/lib/munge
chmod 400 /etc/munge/munge.key
if ! alive /run/munge/munged.pid; then
    runuser -u munge -- /usr/sbin/munged --pid-file=/run/munge/munged.pid || cannot "munged did not start"
fi

# slurm.conf from what slurmd sees of this machine (a machine's own one is kept aside, and
# stop-local-slurm.sh puts it back)
node=$(slurmd -C | head -1)
host=$(hostname -s)
if [ -s /etc/slurm/slurm.conf ] && ! head -1 /etc/slurm/slurm.conf | grep -qF "$MARK"; then
    mv /etc/slurm/slurm.conf "$STATE/slurm.conf.machine"
fi
cat > /etc/slurm/slurm.conf <<CONF
$MARK: one node, no accounting database
ClusterName=stonedem
SlurmctldHost=$host
SlurmUser=root
AuthType=auth/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
SlurmctldPidFile=$STATE/slurmctld.pid
SlurmdPidFile=$STATE/slurmd.pid
SlurmdSpoolDir=$STATE/spool
StateSaveLocation=$STATE/ctld
SlurmctldLogFile=$STATE/slurmctld.log
SlurmdLogFile=$STATE/slurmd.log
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
# finished jobs stay visible to squeue this long [s]: Snakemake's squeue status checks need it
MinJobAge=600
$node State=UNKNOWN
PartitionName=local Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
alive "$STATE/slurmctld.pid" || slurmctld || cannot "slurmctld did not start ($STATE/slurmctld.log)"
alive "$STATE/slurmd.pid" || slurmd || cannot "slurmd did not start ($STATE/slurmd.log)"
for _ in $(seq 1 60); do
    state=$(sinfo -h -o %T 2>/dev/null | head -1)
    case "$state" in idle*|mix*|alloc*) echo "local SLURM up: partition local, node $host ($state)"; exit 0 ;; esac
    sleep 0.5
done
cannot "the node did not come up within 30 s (sinfo says '${state:-nothing}'; $STATE/slurmd.log)"
