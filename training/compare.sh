#!/usr/bin/env bash
# The runs behind training/README.md's table: each sinew env beside its MuJoCo twin, same
# algorithm, hyperparameters, budget and seed, for each seed in SEEDS (default 0). Two runs at a
# time (one per core).
set -euo pipefail
cd "$(dirname "$0")"
run() { python train.py --no-progress --out "${OUT:-../runs}" "$@"; }
for s in ${SEEDS:-0}; do
  run --seed "$s" --env sinew/InvertedPendulum-v0 --algo ppo & run --seed "$s" --env InvertedPendulum-v5 --algo ppo; wait
  run --seed "$s" --env sinew/Hopper-v0 --algo ppo & run --seed "$s" --env Hopper-v5 --algo ppo; wait
done
for s in ${SEEDS:-0}; do
  run --seed "$s" --env sinew/Hopper-v0 --algo sac --steps 50000 & run --seed "$s" --env Hopper-v5 --algo sac --steps 50000; wait
done
