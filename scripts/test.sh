#!/usr/bin/env bash
# Runs every test (gtest + rostest) through ctest; exits non-zero when any test fails.
# Installs and builds first when needed (scripts/setup.sh).
#
# Usage: scripts/test.sh [ctest args...]      e.g. scripts/test.sh -R enhance
# Env:   IRAF_VO_SANITIZE=1  afterwards also builds the core + unit tests with ASan + UBSan in build-asan/
#                            (IRAF_VO_ASAN_BUILD_DIR) and runs them there (ctest -R gtest); any sanitizer
#                            report fails the run. Default: 1 when CI=true, else 0 (IRAF_VO_SANITIZE=0 opts out).
#                            Without ctest args the main stage then skips the gtests that run there (below).
#        IRAF_VO_SANITIZE_TOOLS=1  also builds the CLI tools with the sanitizers (test_bad_cli then runs them;
#                            otherwise it skips them in build-asan/).
#        IRAF_VO_TSAN=1      afterwards also builds the core + the unit tests that run threads with ThreadSanitizer
#                            in build-tsan/ (IRAF_VO_TSAN_BUILD_DIR) and runs them (the local-mapping thread, the
#                            offline pipeline's threads); any
#                            data race report fails the run. Default: 1 when CI=true, else 0.
#        IRAF_VO_FUZZ=1      afterwards also builds every libFuzzer target (test/fuzz) with clang in build-fuzz/
#                            (IRAF_VO_FUZZ_BUILD_DIR) and runs each for IRAF_VO_FUZZ_SECONDS (default 5) s
#                            (scripts/fuzz.sh): a fuzzer that does not build, or a crash found, fails the run.
#                            Default: 1 when CI=true, else 0.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${IRAF_VO_BUILD_DIR:-$ROOT/build}"
export PATH="/usr/bin:$PATH"

default_on_in_ci() { if [ -n "$1" ]; then echo "$1"; elif [ "${CI:-}" = true ]; then echo 1; else echo 0; fi; }
asan_on=$(default_on_in_ci "${IRAF_VO_SANITIZE:-}")

# Cases that repeat one code path many times for a statistic (two-view initializations by the hundred; 300
# tracked frames; step lengths over 40-100-frame roads; path lengths over stereo roads; a night road and its clean
# twin, rendered by whichever of the two cases runs first) and the counter-tests (the health monitor's faults with
# the monitor off, a fisheye road with the forward keyframe rule off) run in the main stage only: 3-11x slower
# under ASan, the shorter cases of the same programs (or, for the highway tracking, test_tracking_forward_start)
# run that code there.
asan_main_only=(TwoViewNoise.NoisyLowParallaxRefusesUndeterminedTranslations TwoViewNoise.LowParallaxFindsTheTrueMotion
  PoseCovariance.ConsistentWithTheFrameToFrameErrorOnASimulation
  TrackingHighwayScale.StepLengthHoldsOnFarPointsNearTheParallaxGate TrackingHighwayScale.FisheyeStepLengthHoldsWithTheForwardRule
  TrackingHighwayScale.StepLengthHoldsWhileTheNearPointsRunOut
  StereoKeyframes.RoadPathIsMetric StereoKeyframes.FisheyeRoadStepsKeepTheirLength
  StereoKeyframes.WeakMetricScaleIsReportedOnTheNightRoad StereoKeyframes.WeakMetricScaleReachesTheSession
  TrackingHealth.WithoutTheMonitorTheseFaultsPassAsTracking)

# When the ASan stage runs (CI) and no ctest arguments are given, the main stage builds and runs only what that stage
# does not: the rostests and other non-gtest tests, the gtests that call the command-line tools (not built with the
# sanitizers, so those cases skip there: the sources that name IRAF_VO_BIN_DIR) and the gtests of the asan_main_only
# cases. Every other gtest runs once, under ASan + UBSan.
main_gtests=() asan_gtests=()
if [ "$asan_on" = 1 ] && [ $# -eq 0 ]; then
  cases=("${asan_main_only[@]/./, *}")  # Suite.Name -> "Suite, *Name", as in TEST(Suite, Name)
  main_re="IRAF_VO_BIN_DIR|TEST(_F|_P)?\(($(IFS='|'; echo "${cases[*]}"))\)"
  for src in "$ROOT"/test/unit/test_*.cpp "$ROOT"/test/ros_unit/test_*.cpp; do
    if grep -Eq "$main_re" "$src"; then main_gtests+=("$(basename "$src" .cpp)"); else asan_gtests+=("$(basename "$src" .cpp)"); fi
  done
fi

"$ROOT/scripts/setup.sh"
if [ ${#main_gtests[@]} -gt 0 ]; then
  cmake -S "$ROOT" -B "$BUILD_DIR" -DIRAF_VO_SELECTED_TESTS="^(rostest_.*|$(IFS='|'; echo "${main_gtests[*]}"))\$" >/dev/null
  cmake --build "$BUILD_DIR" --target selected_tests -j"$(nproc)"
else
  cmake --build "$BUILD_DIR" --target tests -j"$(nproc)"
fi

export ROS_HOME="$BUILD_DIR/ros_home" ROS_LOG_DIR="$BUILD_DIR/ros_home/log"
export ROSCONSOLE_STDOUT_LINE_BUFFERED=1
mkdir -p "$ROS_LOG_DIR"
rm -rf "$BUILD_DIR/test_results"
cd "$BUILD_DIR"
status=0
if [ ${#main_gtests[@]} -gt 0 ]; then
  echo "test.sh: the ASan + UBSan stage runs the other ${#asan_gtests[@]} gtests; here: ${main_gtests[*]}, the rostests"
  ctest --output-on-failure -j"$(nproc)" -E "_gtest_($(IFS='|'; echo "${asan_gtests[*]}"))\$" || status=$?
else
  ctest --output-on-failure -j"$(nproc)" "$@" || status=$?
fi
# ctest runs each gtest/rostest wrapped by catkin; catkin_test_results also catches a test binary
# whose XML reports failures while its wrapper exited 0.
if [ -d "$BUILD_DIR/test_results" ]; then
  catkin_test_results "$BUILD_DIR/test_results" || status=1
fi

# ---- sanitizer stages: configure + build in their own build dir, run the given ctest regex ----
# sanitizer_stage NAME DIR SANITIZE_VALUE CTEST_REGEX TEST_SELECTION [EXTRA_TARGET...]
# TEST_SELECTION: regex of the gtests to build (CMake's selected_tests target: one target, so they compile in
# parallel; a list of --target names is built one after the other).
sanitizer_stage() {
  local name="$1" dir="$2" value="$3" regex="$4" selection="$5"
  shift 5
  local t0
  t0=$(date +%s)
  mkdir -p "$dir"
  export ROS_HOME="$dir/ros_home" ROS_LOG_DIR="$dir/ros_home/log"
  mkdir -p "$ROS_LOG_DIR"
  # A unity build (CMake batches 8 sources per compiler run; sources with their own compile options stay apart): the
  # core's sources share their Eigen / Ceres template instances, ~0.7x the compiler time of one run per source.
  cmake -S "$ROOT" -B "$dir" -DCMAKE_BUILD_TYPE=Release -DIRAF_VO_SANITIZE="$value" -DCMAKE_UNITY_BUILD=ON \
    -DPYTHON_EXECUTABLE=/usr/bin/python3 -DPython3_EXECUTABLE=/usr/bin/python3 \
    -DCATKIN_ENABLE_TESTING=ON -DIRAF_VO_SELECTED_TESTS="$selection" >"$dir/cmake.log" 2>&1 \
    || { cat "$dir/cmake.log"; echo "test.sh: $name cmake configure failed" >&2; exit 1; }
  cmake --build "$dir" --target selected_tests -j"$(nproc)"
  if [ $# -gt 0 ]; then cmake --build "$dir" --target "$@" -j"$(nproc)"; fi
  rm -rf "$dir/test_results"
  echo "test.sh: running the unit tests under $name ($dir)"
  (cd "$dir" && ctest --output-on-failure -j"$(nproc)" -R "$regex") || status=1
  if [ -d "$dir/test_results" ]; then
    catkin_test_results "$dir/test_results" || status=1
  fi
  echo "test.sh: $name stage took $(( $(date +%s) - t0 )) s"
}
# ASan + UBSan: core library + every gtest (test/unit, and test/ros_unit with the ROS glue). LeakSanitizer needs ptrace-like access (works as root / with
# CAP_SYS_PTRACE; set detect_leaks=0 where it cannot run). Every UBSan check is fatal (CMakeLists.txt).
if [ "$asan_on" = 1 ]; then
  targets=()
  if [ "${IRAF_VO_SANITIZE_TOOLS:-0}" = 1 ]; then
    for f in "$ROOT"/src/tools/*.cpp; do targets+=("$(basename "$f" .cpp)"); done
  fi
  export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1}"
  export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
  export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$ROOT/test/sanitizers/lsan.supp:print_suppressions=0}"
  export GTEST_FILTER="${IRAF_VO_ASAN_GTEST_FILTER:-*-$(IFS=:; echo "${asan_main_only[*]}")}"
  sanitizer_stage "ASan + UBSan" "${IRAF_VO_ASAN_BUILD_DIR:-$ROOT/build-asan}" ON gtest '^test_' ${targets[@]+"${targets[@]}"}
  unset GTEST_FILTER
fi

# ThreadSanitizer: core + the tests that run threads: the tracking thread + the local-mapping thread
# (test_tracking_roles, test_tracking_pipeline with mapping_thread on) and the offline pipeline's reader and
# front-end threads (test_pipeline_frontend). Tests that track with mapping_thread off run one thread: not here.
if [ "$(default_on_in_ci "${IRAF_VO_TSAN:-}")" = 1 ]; then
  tsan_tests=(test_tracking_roles test_tracking_pipeline test_pipeline_frontend)
  export TSAN_OPTIONS="${TSAN_OPTIONS:-halt_on_error=1:second_deadlock_stack=1:suppressions=$ROOT/test/sanitizers/tsan.supp}"
  tsan_regex="($(IFS='|'; echo "${tsan_tests[*]}"))\$"
  sanitizer_stage ThreadSanitizer "${IRAF_VO_TSAN_BUILD_DIR:-$ROOT/build-tsan}" thread "gtest_$tsan_regex" "^$tsan_regex"
fi
# libFuzzer targets: the README's fuzz command, a few seconds per target (a long run: scripts/fuzz.sh --seconds 600).
if [ "$(default_on_in_ci "${IRAF_VO_FUZZ:-}")" = 1 ]; then
  t0=$(date +%s)
  # fuzz.sh's own sanitizer options, not the ASan stage's above.
  (unset ASAN_OPTIONS UBSAN_OPTIONS LSAN_OPTIONS; "$ROOT/scripts/fuzz.sh" --seconds "${IRAF_VO_FUZZ_SECONDS:-5}") \
    || { echo "test.sh: fuzz stage failed" >&2; status=1; }
  echo "test.sh: fuzz stage took $(( $(date +%s) - t0 )) s"
fi
exit $status
