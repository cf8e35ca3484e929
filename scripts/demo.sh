#!/usr/bin/env bash
# The package's main job on a built-in default: generate a synthetic illumination-challenge sequence
# (no data needed), run the IRAF pipeline and the ORB-SLAM-style baseline on it, and compare.
#
# Usage: scripts/demo.sh [--dataset DIR_OR_BAG [--topic T] [--gt GT]] [--preset mixed] [--out DIR]
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${IRAF_VO_BUILD_DIR:-$ROOT/build}"
export PATH="/usr/bin:$PATH"

DATASET="" TOPIC="" GT="" PRESET="mixed" OUT="${TMPDIR:-/tmp}/iraf_vo_demo"
while [ $# -gt 0 ]; do
  case "$1" in
    --dataset) DATASET="$2"; shift ;;
    --topic) TOPIC="$2"; shift ;;
    --gt) GT="$2"; shift ;;
    --preset) PRESET="$2"; shift ;;
    --out) OUT="$2"; shift ;;
    -h|--help) sed -n '2,6p' "$0"; exit 0 ;;
    *) echo "demo.sh: unknown argument '$1'" >&2; exit 2 ;;
  esac
  shift
done

if [ ! -f "$BUILD_DIR/devel/setup.bash" ] || [ ! -x "$BUILD_DIR/devel/lib/iraf_vo/iraf_vo_enhance" ]; then
  "$ROOT/scripts/setup.sh"
fi
BIN="$BUILD_DIR/devel/lib/iraf_vo"
mkdir -p "$OUT"

if [ -z "$DATASET" ]; then
  DATASET="$OUT/sequence_$PRESET"
  echo "== generating the synthetic '$PRESET' sequence in $DATASET"
  "$BIN/iraf_vo_simulate" --preset "$PRESET" --out "$DATASET"
  GT="$DATASET/groundtruth.txt"
fi

if [ -x "$BIN/iraf_vo_run" ]; then
  for mode in iraf baseline; do
    echo "== iraf_vo_run --mode $mode"
    args=(--dataset "$DATASET" --mode "$mode" --out "$OUT/traj_$mode.txt" --stats "$OUT/stats_$mode.json")
    [ -n "$TOPIC" ] && args+=(--topic "$TOPIC")
    [ -n "$GT" ] && args+=(--gt "$GT")
    "$BIN/iraf_vo_run" "${args[@]}" | tee "$OUT/summary_$mode.txt"
  done
  echo "== trajectories: $OUT/traj_iraf.txt $OUT/traj_baseline.txt (TUM format)"
else
  echo "== enhancing $DATASET"
  "$BIN/iraf_vo_enhance" "$DATASET" "$OUT/enhanced"
fi
