#!/usr/bin/env bash
# Rebuild one family of native kernels (src/<family>) into the source tree's aaeval/native/,
# incrementally, without reinstalling: bash scripts/build_native_dev.sh <family> [cmake args]
# (with -DAAEVAL_SANITIZE=ON for an ASan/UBSan build). For a normal editable install use
# `pip install --no-build-isolation -e .` (see README, Development).
set -euo pipefail
cd "$(dirname "$0")/.."
family=${1:?usage: build_native_dev.sh <family> [cmake args]}; shift
build=build/dev-$family
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DAAEVAL_DEV_OUTPUT=ON \
  -DAAEVAL_FAMILY="$family" -DPython_EXECUTABLE="$(command -v python3)" "$@" >/dev/null
cmake --build "$build"
