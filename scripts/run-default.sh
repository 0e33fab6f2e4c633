#!/usr/bin/env bash
# Installs what is missing, builds, and runs the main job on the default scene.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
export LC_ALL=C
cmake -S . -B build >/dev/null
cmake --build build -j"$(nproc)" >&2
./build/headplan paper scenarios/paper_expansion.yaml scenarios/paper_compression.yaml
