# Sourced by the tests that need a running Slurm: slurm_start DIR starts munged, slurmctld
# and slurmd on 127.0.0.1 with a fresh munge key and a slurm.conf written under DIR, and
# exports SLURM_CONF so that sbatch, squeue and scancel talk to them; slurm_stop stops all
# three (call it from the caller's EXIT trap). slurm_start returns 1 with the reason in
# $slurm_why when the services cannot start here (packages missing, not root).
slurm_pids=()
slurm_why=
# slurm_free_port: a TCP port on 127.0.0.1 that nothing listens on now.
slurm_free_port() {
    python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}
# slurm_wait SECONDS COMMAND...: polls COMMAND every half second until it succeeds.
slurm_wait() {
    local end=$((SECONDS + $1)); shift
    until "$@" >/dev/null 2>&1; do
        (( SECONDS < end )) || return 1
        sleep 0.5
    done
}
slurm_start() {
    local d=$1 p
    for p in munged mungekey slurmctld slurmd sbatch squeue scancel scontrol; do
        command -v "$p" >/dev/null || PATH="$PATH:/usr/sbin" command -v "$p" >/dev/null \
            || { slurm_why="$p not installed (Debian packages munge, slurm-wlm)"; return 1; }
    done
    PATH="$PATH:/usr/sbin"
    # slurmd runs jobs as their submitting user, which needs root.
    [ "$(id -u)" -eq 0 ] || { slurm_why="slurmd must run as root to start jobs (uid $(id -u))"; return 1; }
    mkdir -p "$d/munge" "$d/state" "$d/spool" && chmod 700 "$d/munge" || return 1
    mungekey --create --keyfile="$d/munge/munge.key" >/dev/null 2>&1 \
        || { slurm_why="mungekey could not create a key"; return 1; }
    munged --force --socket="$d/munge/socket" --key-file="$d/munge/munge.key" \
        --pid-file="$d/munge/munged.pid" --log-file="$d/munge/munged.log" \
        --seed-file="$d/munge/seed" >/dev/null 2>&1 \
        || { slurm_why="munged did not start: $(tail -n 1 "$d/munge/munged.log" 2>/dev/null)"; return 1; }
    slurm_pids+=("$(cat "$d/munge/munged.pid")")
    local host; host=$(hostname -s)
    cat > "$d/slurm.conf" <<CONF
ClusterName=headplan-test
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$(slurm_free_port)
SlurmdPort=$(slurm_free_port)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$d/munge/socket
StateSaveLocation=$d/state
SlurmdSpoolDir=$d/spool
SlurmctldPidFile=$d/slurmctld.pid
SlurmdPidFile=$d/slurmd.pid
SlurmctldLogFile=$d/slurmctld.log
SlurmdLogFile=$d/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MpiDefault=none
KillWait=5
InactiveLimit=0
MinJobAge=300
NodeName=$host NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
    export SLURM_CONF="$d/slurm.conf"
    slurmctld -c -f "$SLURM_CONF" >"$d/slurmctld.out" 2>&1 \
        || { slurm_why="slurmctld did not start: $(tail -n 2 "$d/slurmctld.log" 2>/dev/null)"; return 1; }
    slurm_wait 60 test -s "$d/slurmctld.pid" && slurm_pids+=("$(cat "$d/slurmctld.pid")")
    slurmd -f "$SLURM_CONF" >"$d/slurmd.out" 2>&1 \
        || { slurm_why="slurmd did not start: $(tail -n 2 "$d/slurmd.log" 2>/dev/null)"; return 1; }
    slurm_wait 60 test -s "$d/slurmd.pid" && slurm_pids+=("$(cat "$d/slurmd.pid")")
    # Generous: the CI machine is loaded on purpose.
    slurm_wait 120 slurm_node_idle \
        || { slurm_why="the node did not come up: $(tail -n 2 "$d/slurmd.log" 2>/dev/null)"; return 1; }
}
slurm_node_idle() { sinfo -h -o %t 2>/dev/null | grep -qx 'idle'; }
slurm_stop() {
    local p
    for p in "${slurm_pids[@]}"; do kill "$p" 2>/dev/null; done
    for p in "${slurm_pids[@]}"; do slurm_wait 30 bash -c "! kill -0 $p"; done
    for p in "${slurm_pids[@]}"; do kill -KILL "$p" 2>/dev/null; done
    slurm_pids=()
}
