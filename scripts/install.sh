#!/usr/bin/env bash
# Installs aaeval and everything it needs: the Python package with its test extra and the
# cvvdp extra (ColorVideoVDP and a CPU build of PyTorch, for the perceptual temporal metric
# the default experiment measures), its C++ kernels compiled on the way by scikit-build-core
# and CMake, and on Debian-like
# machines a C++ compiler and CMake where missing and the shared libLLVM that Mitsuba's
# LLVM variant loads.
set -euo pipefail
cd "$(dirname "$0")/.."
PY=${PYTHON:-python3}

have_llvm() {  # a libLLVM >= 16 where aaeval.mitsuba_variant looks first
  local f
  for f in /usr/lib/*-linux-gnu/libLLVM.so.1[6-9]* /usr/lib/*-linux-gnu/libLLVM-1[6-9]*.so* \
           /usr/lib/*-linux-gnu/libLLVM.so.[2-9][0-9]* /usr/lib/llvm-1[6-9]/lib/libLLVM*.so*; do
    [ -e "$f" ] && return 0
  done
  return 1
}

# the native kernels (src/, CMakeLists.txt) need a C++17 compiler and CMake >= 3.18
if ! command -v c++ >/dev/null 2>&1 || ! command -v cmake >/dev/null 2>&1; then
  if command -v apt-get >/dev/null 2>&1 && [ "$(id -u)" = 0 ]; then
    echo "installing a C++ compiler and CMake for the native kernels"
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq build-essential cmake >/dev/null
  else
    echo "error: the native kernels need a C++17 compiler and CMake (Debian: apt-get install build-essential cmake)" >&2
    exit 1
  fi
fi

if ! have_llvm && [ -z "${DRJIT_LIBLLVM_PATH:-}" ]; then
  if command -v apt-get >/dev/null 2>&1 && [ "$(id -u)" = 0 ]; then
    echo "installing libllvm19 for Mitsuba's LLVM variant"
    (apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libllvm19 >/dev/null) \
      || echo "warning: could not install libllvm19; Mitsuba falls back to scalar_rgb (slow)" >&2
  else
    echo "note: no libLLVM >= 16 found. Install LLVM 16+ (e.g. 'apt-get install libllvm19' or 'brew install llvm')" >&2
    echo "      or set DRJIT_LIBLLVM_PATH; otherwise Mitsuba runs its slow scalar_rgb variant." >&2
  fi
fi

# AAEVAL_INSTALL_BROWSER=1 (CI sets it): Debian's chromium for the report's browser test,
# driven by Playwright through the system executable (no browser is ever downloaded).
if [ -n "${AAEVAL_INSTALL_BROWSER:-}" ] && ! command -v chromium >/dev/null 2>&1; then
  if command -v apt-get >/dev/null 2>&1 && [ "$(id -u)" = 0 ]; then
    echo "installing chromium for the report's browser test"
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null
  else
    echo "error: AAEVAL_INSTALL_BROWSER is set but chromium cannot be installed (needs apt-get as root)" >&2
    exit 1
  fi
fi

"$PY" -m pip install -q --disable-pip-version-check -e ".[test,cvvdp]"
# An editable install leaves the sources uncompiled (pip byte-compiles only what it copies):
# compile them once here, so that every process importing aaeval (the CLI, sweep workers,
# the tests' subprocesses) reads bytecode even where PYTHONDONTWRITEBYTECODE is set, instead
# of compiling ~110 modules each time. Python still checks each file's date: an edited
# module is compiled afresh, never read stale.
"$PY" -m compileall -q aaeval >/dev/null
