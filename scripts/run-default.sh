#!/usr/bin/env bash
# Installs what is missing, builds, and runs the main job on the default scene.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
export LC_ALL=C
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" >&2
# The main job: the default scene (the paper's eight-bladder layout, default adult head,
# a small 6-DOF correction) -> the eight pressures, the achieved pose and the status.
./build/headplan solve scenarios/default.yaml
