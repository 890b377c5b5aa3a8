#!/usr/bin/env bash
# Stops the Slurm started by start_slurm.sh DIR: only the process ids it wrote to DIR/pids.
set -u
DIR=${1:?usage: stop_slurm.sh DIR}
[ -f "$DIR/pids" ] || exit 0
pids=$(tac "$DIR/pids")
for p in $pids; do kill "$p" 2>/dev/null || true; done
for _ in $(seq 50); do
  alive=0
  for p in $pids; do kill -0 "$p" 2>/dev/null && alive=1; done
  [ $alive = 0 ] && exit 0
  sleep 0.1
done
for p in $pids; do kill -9 "$p" 2>/dev/null || true; done
exit 0
