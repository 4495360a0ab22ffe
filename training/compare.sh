#!/usr/bin/env bash
# The runs behind training/README.md's table: each sinew env beside its MuJoCo twin, same
# algorithm, hyperparameters, budget and seed. Two runs at a time (one per core).
set -euo pipefail
cd "$(dirname "$0")"
run() { python train.py --no-progress --out "${OUT:-../runs}" "$@"; }
run --env sinew/InvertedPendulum-v0 --algo ppo & run --env InvertedPendulum-v5 --algo ppo; wait
run --env sinew/Hopper-v0 --algo ppo & run --env Hopper-v5 --algo ppo; wait
run --env sinew/Hopper-v0 --algo sac --steps 50000 & run --env Hopper-v5 --algo sac --steps 50000; wait
