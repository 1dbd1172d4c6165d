# What start-local-slurm.sh and stop-local-slurm.sh share (sourced by both, not run): where the
# daemons' state lives, and the first line that marks the slurm.conf the start wrote, by which
# the stop knows to remove it.
STATE=${STONEDEM_SLURM_STATE:-/var/tmp/stonedem-slurm}
MARK="# written by stonedem workflow/cluster/start-local-slurm.sh"
