#!/usr/bin/env bash
# The fuzz corpus through the native kernels built with AddressSanitizer and
# UndefinedBehaviorSanitizer (issue 20):
#
#   bash scripts/fuzz_native.sh [fuzz_cli.py arguments, e.g. --cases 300]
#   FAMILY=samplers bash scripts/fuzz_native.sh --cases 300   # one family of src/ only
#
# Builds every family of src/ (or only $FAMILY) with -DAAEVAL_SANITIZE=ON in its own build
# folder ($ASAN_DIR/build, default build/asan-<family or all>) and installs the modules to
# $ASAN_DIR/install, never touching the source tree's modules that other work imports (nor
# another run's folder: one folder per family). A copy of the Python package in
# $ASAN_DIR/pkg gets the sanitized modules (a family not rebuilt keeps its plain module,
# and is named as such); a sitecustomize.py there puts the copy first on sys.path and drops
# the editable install's import redirect, so `import aaeval` finds the copy. Then
# scripts/fuzz_cli.py runs (10,000 cases by default) with libasan (and libstdc++) preloaded, leak checks
# off (Python's interned objects live to the end) and UBSan halting on the first error.
# Prints a summary: the modules sanitized, the fuzz verdicts and every sanitizer report.
# The log is $ASAN_DIR/fuzz.log; failing cases go to $ASAN_DIR/failures/.
set -uo pipefail
cd "$(dirname "$0")/.."
root=$PWD
family=${FAMILY:-}
base=$(realpath -m "${ASAN_DIR:-build/asan-${family:-all}}")
build=$base/build
prefix=$base/install
pkg=$base/pkg
log=$base/fuzz.log
failures=$base/failures
mkdir -p "$base"
jobs=${JOBS:-2}

echo "== building the native kernels with ASan + UBSan (${family:-all families}) in $build"
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DAAEVAL_SANITIZE=ON -DAAEVAL_DEV_OUTPUT=OFF \
  -DAAEVAL_FAMILY="$family" -DPython_EXECUTABLE="$(command -v python3)" >/dev/null || exit 1
cmake --build "$build" -j "$jobs" || exit 1
rm -rf "$prefix"
cmake --install "$build" --prefix "$prefix" >/dev/null || exit 1

echo "== package copy with the sanitized modules in $pkg"
rm -rf "$pkg"
python3 - "$root" "$pkg" "$prefix" <<'PY' || exit 1
import pathlib, shutil, sys
root, pkg, prefix = (pathlib.Path(p) for p in sys.argv[1:])
shutil.copytree(root / "aaeval", pkg / "aaeval", ignore=shutil.ignore_patterns("*.so", "__pycache__"))
built = sorted((prefix / "aaeval" / "native").glob("*.so"))
for so in built:
    shutil.copy2(so, pkg / "aaeval" / "native" / so.name)
    print(f"  sanitized: aaeval.native.{so.name.split('.')[0]}")
names = {so.name for so in built}
for so in sorted((root / "aaeval" / "native").glob("*.so")):
    if so.name not in names:
        shutil.copy2(so, pkg / "aaeval" / "native" / so.name)
        print(f"  NOT sanitized (plain build from the source tree): aaeval.native.{so.name.split('.')[0]}")
(pkg / "sitecustomize.py").write_text(
    "# written by scripts/fuzz_native.sh: import aaeval from this copy (sanitized modules)\n"
    "import os, sys\n"
    "here = os.path.dirname(os.path.abspath(__file__))\n"
    "sys.meta_path[:] = [f for f in sys.meta_path if not type(f).__module__.startswith('_editable_skbc_')]\n"
    "if here in sys.path:\n"
    "    sys.path.remove(here)\n"
    "sys.path.insert(0, here)\n")
PY

# libstdc++ preloaded too: python3 does not link it, and ASan's __cxa_throw interceptor,
# set up when libasan starts, then finds no real __cxa_throw ("CHECK failed:
# asan_interceptors.cpp ... real___cxa_throw") at the first C++ exception (matplotlib's)
libasan=$(gcc -print-file-name=libasan.so)
libstdcxx=$(gcc -print-file-name=libstdc++.so)
export LD_PRELOAD="$libasan $libstdcxx"
export ASAN_OPTIONS=detect_leaks=0:halt_on_error=1:abort_on_error=0:symbolize=1
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
export PYTHONPATH=$pkg
check=$(cd "$pkg" && python3 -c "
import importlib, pathlib, aaeval
mods = sorted(p.name.split('.')[0] for p in (pathlib.Path(aaeval.__file__).parent / 'native').glob('*.so'))
for m in mods:
    print(m, importlib.import_module('aaeval.native.' + m).__file__)
" 2>&1) || { echo "the sanitized package does not import:"; echo "$check"; exit 1; }
echo "$check" | sed 's/^/  imports: /'
case "$check" in *"$pkg"*) ;; *) echo "aaeval was not imported from $pkg"; exit 1 ;; esac

echo "== fuzz_cli.py $* under ASan/UBSan (log: $log)"
start=$(date +%s)
python3 "$root/scripts/fuzz_cli.py" --failures "$failures" "$@" >"$log" 2>&1
code=$?
end=$(date +%s)

asan=$(grep -c "ERROR: AddressSanitizer\|AddressSanitizer: CHECK failed" "$log")
ubsan=$(grep -c "runtime error:" "$log")
echo "== summary"
echo "  fuzz_cli exit code: $code ($((end - start)) s)"
grep -E "^[0-9]+ cases in|^  (image|refused|traceback|bad-exit|not-one-line|hang|bad-output|outside-changed|memory) |^failures:|^files changed" "$log" | sed 's/^/  /'
echo "  AddressSanitizer reports: $asan"
echo "  UndefinedBehaviorSanitizer reports: $ubsan"
if [ "$asan" -gt 0 ] || [ "$ubsan" -gt 0 ]; then
  grep -E -A25 "ERROR: AddressSanitizer|AddressSanitizer: CHECK failed|runtime error:" "$log" | head -80
fi
if [ "$code" -ne 0 ] && [ "$asan" -eq 0 ] && [ "$ubsan" -eq 0 ]; then
  echo "  (no sanitizer report; the end of the log:)"
  tail -20 "$log"
fi
[ "$code" -eq 0 ] && [ "$asan" -eq 0 ] && [ "$ubsan" -eq 0 ]
