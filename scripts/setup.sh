#!/usr/bin/env bash
# Installs every Debian package iraf_vo needs (idempotent) and builds the package in build/ (Release).
# Afterwards:  source build/devel/setup.bash   (rospack find / roslaunch / rostest / rosrun iraf_vo ...)
#
# Usage: scripts/setup.sh [--no-install] [--no-build] [--debug] [-- extra cmake args]
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${IRAF_VO_BUILD_DIR:-$ROOT/build}"
INSTALL=1
BUILD=1
BUILD_TYPE=Release
EXTRA=()
while [ $# -gt 0 ]; do
  case "$1" in
    --no-install) INSTALL=0 ;;
    --no-build) BUILD=0 ;;
    --debug) BUILD_TYPE=Debug ;;
    --) shift; EXTRA=("$@"); break ;;
    -h|--help) sed -n '2,6p' "$0"; exit 0 ;;
    *) echo "setup.sh: unknown argument '$1'" >&2; exit 2 ;;
  esac
  shift
done

# A pyenv/conda python3 first on PATH lacks Debian's catkin_pkg, rospkg, em, yaml...: use Debian's.
export PATH="/usr/bin:$PATH"

PACKAGES=(
  build-essential cmake pkg-config
  ros-base-dev libimage-transport-dev libcv-bridge-dev libtf2-ros-dev libtf2-geometry-msgs-dev
  python3-dynamic-reconfigure python3-roslib python3-rostest python3-rosbag python3-roslaunch rosbash
  python3-rosnode python3-rostopic python3-rosservice python3-rosparam python3-std-srvs libstd-srvs-dev
  python3-sensor-msgs python3-geometry-msgs python3-nav-msgs python3-tf2-msgs
  libdiagnostic-updater-dev python3-diagnostic-msgs python3-diagnostic-updater
  python3-tf2-ros tf2-tools image-transport-tools
  libceres-dev libeigen3-dev libopencv-dev libyaml-cpp-dev libgtest-dev libdeflate-dev
  python3-numpy python3-matplotlib python3-yaml python3-opencv
  opencv-doc rviz
)
# What the README's commands use besides the build: `rostopic echo /diagnostics` (python3-diagnostic-msgs; the
# nodelets publish through diagnostic_updater), `rosrun tf2_tools echo.py world cam0` (tf2-tools: Debian ships no
# tf2_echo binary, tf2_tools' echo.py is the same check; view_frames.py too), tf2_ros' python API
# (python3-tf2-ros), `rosrun image_transport list_transports` / `republish` (image-transport-tools).
# screenshots of rviz without a display (scripts/rviz_screenshot.sh: xvfb-run, imagemagick's import): IRAF_VO_WITH_XVFB=1
if [ "${IRAF_VO_WITH_XVFB:-0}" = 1 ]; then PACKAGES+=(xvfb x11-apps imagemagick); fi

if [ "$INSTALL" = 1 ]; then
  missing=()
  for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    SUDO=""
    if [ "$(id -u)" != 0 ]; then
      command -v sudo >/dev/null || { echo "setup.sh: not root and no sudo; install: ${missing[*]}" >&2; exit 1; }
      SUDO="sudo"
    fi
    echo "setup.sh: installing ${#missing[@]} Debian packages: ${missing[*]}"
    $SUDO apt-get update -q
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
  else
    echo "setup.sh: all ${#PACKAGES[@]} Debian packages present"
  fi
fi

if [ "$BUILD" = 1 ]; then
  mkdir -p "$BUILD_DIR"
  export ROS_HOME="$BUILD_DIR/ros_home" ROS_LOG_DIR="$BUILD_DIR/ros_home/log"
  cmake -S "$ROOT" -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE="$BUILD_TYPE" \
    -DPYTHON_EXECUTABLE=/usr/bin/python3 -DPython3_EXECUTABLE=/usr/bin/python3 \
    -DCATKIN_ENABLE_TESTING=ON "${EXTRA[@]}" >"$BUILD_DIR/cmake.log" 2>&1 \
    || { cat "$BUILD_DIR/cmake.log"; echo "setup.sh: cmake configure failed" >&2; exit 1; }
  cmake --build "$BUILD_DIR" -j"$(nproc)"
  echo "setup.sh: built in $BUILD_DIR ($BUILD_TYPE). Now: source $BUILD_DIR/devel/setup.bash"
fi
