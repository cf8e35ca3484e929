#!/usr/bin/env bash
# A screenshot of rviz (rviz/iraf_vo.rviz) following the camera through the whole pipeline, without a display:
# renders a simulated bag (iraf_vo_simulate --bag), runs `euroc.launch bag:=... rviz:=true` under xvfb-run on its
# own ROS master, grabs the virtual screen with imagemagick's `import -window root` after --after seconds of
# playback, then crops and shrinks it (docs/images/rviz.png, referenced by docs/ros_interface.md).
#
# Usage: scripts/rviz_screenshot.sh [--out PNG] [--bag BAG --camera-file YAML] [--after SEC] [--width PX]
#                                   [--preset clean] [--frames N] [--port P]
# Needs xvfb, imagemagick and rviz: IRAF_VO_WITH_XVFB=1 scripts/setup.sh installs them.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${IRAF_VO_BUILD_DIR:-$ROOT/build}"
export PATH="/usr/bin:$PATH"

OUT="$ROOT/docs/images/rviz.png" BAG="" CAMERA_FILE="" AFTER="14" WIDTH="960" PRESET="clean" FRAMES="400" PORT="11391"
while [ $# -gt 0 ]; do
  case "$1" in
    --out) OUT="$2"; shift ;;
    --bag) BAG="$2"; shift ;;
    --camera-file) CAMERA_FILE="$2"; shift ;;
    --after) AFTER="$2"; shift ;;
    --width) WIDTH="$2"; shift ;;
    --preset) PRESET="$2"; shift ;;
    --frames) FRAMES="$2"; shift ;;
    --port) PORT="$2"; shift ;;
    -h|--help) sed -n '2,9p' "$0"; exit 0 ;;
    *) echo "rviz_screenshot.sh: unknown argument '$1'" >&2; exit 2 ;;
  esac
  shift
done
for tool in xvfb-run import convert rviz; do
  command -v "$tool" >/dev/null || { echo "rviz_screenshot.sh: '$tool' missing (IRAF_VO_WITH_XVFB=1 scripts/setup.sh)" >&2; exit 1; }
done
[ -f "$BUILD_DIR/devel/setup.bash" ] || { echo "rviz_screenshot.sh: no build in $BUILD_DIR (scripts/setup.sh)" >&2; exit 1; }
set +u  # ROS's setup scripts read unset variables
# shellcheck disable=SC1091
source "$BUILD_DIR/devel/setup.bash"
set -u

WORK="$(mktemp -d "${TMPDIR:-/tmp}/iraf_vo_rviz.XXXXXX")"
trap 'rm -rf "$WORK"' EXIT
if [ -z "$BAG" ]; then
  echo "== rendering a simulated '$PRESET' room sequence ($FRAMES frames) into a bag"
  "$BUILD_DIR/devel/lib/iraf_vo/iraf_vo_simulate" --preset "$PRESET" --frames "$FRAMES" --out "$WORK/sim" \
    --bag "$WORK/sim.bag" >"$WORK/simulate.log" 2>&1 || { cat "$WORK/simulate.log"; exit 1; }
  BAG="$WORK/sim.bag"
  CAMERA_FILE="$WORK/sim/mav0/cam0/sensor.yaml"
fi
[ -n "$CAMERA_FILE" ] || { echo "rviz_screenshot.sh: --bag needs --camera-file" >&2; exit 2; }

# Own master and logs: no clash with a running roscore or a parallel test.
export ROS_MASTER_URI="http://localhost:$PORT" ROS_HOME="$WORK/ros_home" ROS_LOG_DIR="$WORK/ros_home/log"
mkdir -p "$ROS_LOG_DIR" "$(dirname "$OUT")"
echo "== euroc.launch bag:=$BAG rviz:=true under xvfb-run, screenshot after ${AFTER} s of playback"
xvfb-run -a -s "-screen 0 1600x1000x24" bash -c '
  roslaunch -p "$1" iraf_vo euroc.launch bag:="$2" camera_file:="$3" rviz:=true >"$4/launch.log" 2>&1 &
  launch=$!
  sleep "$5"
  import -window root "$4/full.png"
  kill -INT "$launch"
  wait "$launch" || true
' _ "$PORT" "$BAG" "$CAMERA_FILE" "$WORK" "$((AFTER + 6))"
[ -s "$WORK/full.png" ] || { echo "rviz_screenshot.sh: no screenshot; launch log:" >&2; tail -30 "$WORK/launch.log" >&2; exit 1; }
# rviz opens at its saved window size in the top-left corner; keep that, shrink, and store a small palette PNG.
convert "$WORK/full.png" -trim +repage -resize "${WIDTH}x>" -colors 256 -strip "$OUT"
echo "rviz_screenshot.sh: wrote $OUT ($(stat -c %s "$OUT") bytes)"
