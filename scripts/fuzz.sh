#!/usr/bin/env bash
# Builds the libFuzzer targets (test/fuzz/fuzz_*.cpp) with clang -fsanitize=fuzzer,address,undefined in
# build-fuzz/ and runs each for a bounded time. Exits non-zero when any target finds a crash / sanitizer
# error (the reproducer is saved as build-fuzz/artifacts/<target>-crash-*; re-run with: <binary> <file>).
#
# Usage: scripts/fuzz.sh [--seconds N] [--no-install] [--build-only] [target ...]
#   --seconds N   fuzzing time per target (default 60)
#   target        e.g. fuzz_camera_yaml (default: every test/fuzz/fuzz_*.cpp)
# Seeds: test/fuzz/corpus/<target>/ (read only); inputs found are kept in build-fuzz/corpus/<target>/.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${IRAF_VO_FUZZ_BUILD_DIR:-$ROOT/build-fuzz}"
SECONDS_PER_TARGET=60
INSTALL=1
RUN=1
TARGETS=()
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) SECONDS_PER_TARGET="$2"; shift ;;
    --no-install) INSTALL=0 ;;
    --build-only) RUN=0 ;;
    -h|--help) sed -n '2,10p' "$0"; exit 0 ;;
    -*) echo "fuzz.sh: unknown option '$1'" >&2; exit 2 ;;
    *) TARGETS+=("$1") ;;
  esac
  shift
done
export PATH="/usr/bin:$PATH"

# clang 14 + its runtime (libFuzzer, ASan, UBSan) from Debian.
if [ "$INSTALL" = 1 ]; then
  missing=()
  for p in clang-14 libclang-rt-14-dev; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    SUDO=""
    if [ "$(id -u)" != 0 ]; then
      command -v sudo >/dev/null || { echo "fuzz.sh: not root and no sudo; install: ${missing[*]}" >&2; exit 1; }
      SUDO="sudo"
    fi
    echo "fuzz.sh: installing ${missing[*]}"
    $SUDO apt-get update -q
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
  fi
fi

build_targets=(fuzzers)  # every fuzzer through one target: compiled in parallel
if [ ${#TARGETS[@]} -eq 0 ]; then
  for f in "$ROOT"/test/fuzz/fuzz_*.cpp; do TARGETS+=("$(basename "$f" .cpp)"); done
else
  build_targets=("${TARGETS[@]}")
fi

mkdir -p "$BUILD_DIR"
if [ ! -f "$BUILD_DIR/CMakeCache.txt" ]; then
  # A unity build, as scripts/test.sh's sanitizer stages.
  cmake -S "$ROOT" -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_UNITY_BUILD=ON \
    -DCMAKE_C_COMPILER=clang-14 -DCMAKE_CXX_COMPILER=clang++-14 -DIRAF_VO_FUZZ=ON \
    -DCATKIN_ENABLE_TESTING=OFF -DPYTHON_EXECUTABLE=/usr/bin/python3 -DPython3_EXECUTABLE=/usr/bin/python3 \
    >"$BUILD_DIR/cmake.log" 2>&1 || { cat "$BUILD_DIR/cmake.log"; echo "fuzz.sh: cmake configure failed" >&2; exit 1; }
else
  cmake "$BUILD_DIR" >"$BUILD_DIR/cmake.log" 2>&1 || { cat "$BUILD_DIR/cmake.log"; exit 1; }  # new sources
fi
cmake --build "$BUILD_DIR" --target "${build_targets[@]}" -j"$(nproc)"
[ "$RUN" = 1 ] || exit 0

export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:symbolize=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
mkdir -p "$BUILD_DIR/artifacts" "$BUILD_DIR/logs"
failed=()
summary=()
for t in "${TARGETS[@]}"; do
  seeds="$ROOT/test/fuzz/corpus/$t"
  work="$BUILD_DIR/corpus/$t"
  mkdir -p "$work"
  log="$BUILD_DIR/logs/$t.log"
  echo "fuzz.sh: $t for ${SECONDS_PER_TARGET}s (log: $log)"
  bin="$(find "$BUILD_DIR" -maxdepth 4 -type f -name "$t" -perm -u+x | head -1)"
  [ -n "$bin" ] || { echo "fuzz.sh: $t not built" >&2; exit 1; }
  rc=0
  (cd "$BUILD_DIR" && "$bin" -max_total_time="$SECONDS_PER_TARGET" -timeout=20 -rss_limit_mb=2560 -max_len=4096 \
     -print_final_stats=1 -artifact_prefix="$BUILD_DIR/artifacts/$t-" "$work" $( [ -d "$seeds" ] && echo "$seeds" )) \
     >"$log" 2>&1 || rc=$?
  runs=$(grep -o 'Done [0-9]* runs in [0-9]* second' "$log" | tail -1 || true)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 || true)
  if [ "$rc" != 0 ]; then
    failed+=("$t")
    summary+=("$t: FAILED (exit $rc) -- see $log; reproducer(s): $(ls "$BUILD_DIR"/artifacts/"$t"-* 2>/dev/null | tr '\n' ' ')")
    grep -m5 -E 'ERROR: |runtime error|FUZZ_CHECK|terminate|SUMMARY' "$log" || tail -20 "$log"
  else
    summary+=("$t: ok, ${runs:-? runs}s, ${cov:-cov ?}, corpus $(ls "$work" | wc -l) inputs")
  fi
done
echo "fuzz.sh summary:"
printf '  %s\n' "${summary[@]}"
[ ${#failed[@]} -eq 0 ] || { echo "fuzz.sh: ${#failed[@]} target(s) failed: ${failed[*]}" >&2; exit 1; }
