#!/usr/bin/env bash
# Runs every test (gtest + rostest) through ctest; exits non-zero when any test fails.
# Installs and builds first when needed (scripts/setup.sh).
#
# Usage: scripts/test.sh [ctest args...]      e.g. scripts/test.sh -R enhance
# Env:   IRAF_VO_SANITIZE=1  also builds build-asan/ with ASan+UBSan and runs the unit tests there.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${IRAF_VO_BUILD_DIR:-$ROOT/build}"
export PATH="/usr/bin:$PATH"

"$ROOT/scripts/setup.sh"
cmake --build "$BUILD_DIR" --target tests -j"$(nproc)"

export ROS_HOME="$BUILD_DIR/ros_home" ROS_LOG_DIR="$BUILD_DIR/ros_home/log"
export ROSCONSOLE_STDOUT_LINE_BUFFERED=1
mkdir -p "$ROS_LOG_DIR"
rm -rf "$BUILD_DIR/test_results"
cd "$BUILD_DIR"
status=0
ctest --output-on-failure -j"$(nproc)" "$@" || status=$?
# ctest runs each gtest/rostest wrapped by catkin; catkin_test_results also catches a test binary
# whose XML reports failures while its wrapper exited 0.
if [ -d "$BUILD_DIR/test_results" ]; then
  catkin_test_results "$BUILD_DIR/test_results" || status=1
fi
exit $status
