#!/usr/bin/env bash
# The first command of the README: install aaeval, run the default experiment sweep (every
# shipped experiment at a small size) into reports/default/ and write its HTML report.
# Rerunning it resumes: finished cells are kept, only missing ones run. Extra arguments go
# to 'aaeval sweep' (e.g. --workers 1, --quiet).
set -euo pipefail
cd "$(dirname "$0")/.."
PY=${PYTHON:-python3}
OUT=${AAEVAL_QUICKSTART_OUT:-reports/default}

# AAEVAL_SKIP_INSTALL=1: the environment is already set up (CI, a second run)
[ -n "${AAEVAL_SKIP_INSTALL:-}" ] || bash scripts/install.sh
[ -n "${DRJIT_LIBLLVM_PATH:-}" ] || for lib in /usr/lib/x86_64-linux-gnu/libLLVM.so.19.1 /usr/lib/aarch64-linux-gnu/libLLVM.so.19.1; do
  if [ -e "$lib" ]; then export DRJIT_LIBLLVM_PATH="$lib"; break; fi
done

start=$(date +%s)
"$PY" -m aaeval sweep configs/sweeps/default.toml --out "$OUT" "$@"
"$PY" -m aaeval report "$OUT"
echo "default sweep and report took $(( $(date +%s) - start )) s"
echo "report: $(cd "$OUT" && pwd)/index.html  (tables: $OUT/results.parquet)"
