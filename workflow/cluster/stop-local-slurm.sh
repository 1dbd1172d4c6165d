#!/usr/bin/env bash
# Stop what start-local-slurm.sh started: slurmd, slurmctld and munged, each by the PID in its
# PID file (never by process name: other daemons of the machine are left alone), and remove
# the slurm.conf it wrote.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/local-slurm.sh"  # STATE, MARK
for pidfile in "$STATE/slurmd.pid" "$STATE/slurmctld.pid" /run/munge/munged.pid; do
    [ -s "$pidfile" ] || continue
    pid=$(cat "$pidfile")
    if kill -0 "$pid" 2>/dev/null; then
        kill "$pid"
        for _ in $(seq 1 40); do kill -0 "$pid" 2>/dev/null || break; sleep 0.25; done
        kill -0 "$pid" 2>/dev/null && kill -9 "$pid"
    fi
    rm -f "$pidfile"
done
# the slurm.conf it wrote goes too (the machine's own comes back): with a config and no
# controller, every scontrol call waits ~9 s to fail, and Snakemake's SLURM plugin calls it at
# each start
if head -1 /etc/slurm/slurm.conf 2>/dev/null | grep -qF "$MARK"; then
    rm -f /etc/slurm/slurm.conf
    [ -s "$STATE/slurm.conf.machine" ] && mv "$STATE/slurm.conf.machine" /etc/slurm/slurm.conf
fi
echo "local SLURM stopped"
