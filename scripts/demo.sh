#!/usr/bin/env bash
# The package's main job on a built-in default: generate a synthetic poor-light sequence as a camera sees it
# (no data needed; default `night`: a dim room filmed at long exposure and high gain, so the image is noisy), run
# the IRAF pipeline, the ORB-SLAM-style baseline and CLAHE preprocessing on it, and compare them side by side.
#
# Usage: scripts/demo.sh [--dataset DIR_OR_BAG [--topic T] [--gt GT]] [--preset night] [--camera pinhole|fisheye]
#                        [--frames N] [--seed S] [--out DIR]
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${IRAF_VO_BUILD_DIR:-$ROOT/build}"
export PATH="/usr/bin:$PATH"

DATASET="" TOPIC="" GT="" PRESET="night" CAMERA="pinhole" FRAMES="300" SEED="0" OUT="${TMPDIR:-/tmp}/iraf_vo_demo"
while [ $# -gt 0 ]; do
  case "$1" in
    --dataset) DATASET="$2"; shift ;;
    --topic) TOPIC="$2"; shift ;;
    --gt) GT="$2"; shift ;;
    --preset) PRESET="$2"; shift ;;
    --camera) CAMERA="$2"; shift ;;
    --frames) FRAMES="$2"; shift ;;
    --seed) SEED="$2"; shift ;;
    --out) OUT="$2"; shift ;;
    -h|--help) sed -n '2,7p' "$0"; exit 0 ;;
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
  DATASET="$OUT/sequence_${PRESET}_${CAMERA}_$SEED"
  echo "== generating the synthetic '$PRESET' sequence ($CAMERA camera, $FRAMES frames, seed $SEED) in $DATASET"
  "$BIN/iraf_vo_simulate" --preset "$PRESET" --camera "$CAMERA" --frames "$FRAMES" --seed "$SEED" --out "$DATASET"
  GT="$DATASET/groundtruth.txt"
fi

if [ -x "$BIN/iraf_vo_run" ]; then
  for mode in iraf baseline clahe; do
    echo "== iraf_vo_run --mode $mode"
    args=(--dataset "$DATASET" --mode "$mode" --out "$OUT/traj_$mode.txt" --stats "$OUT/stats_$mode.json")
    [ -n "$TOPIC" ] && args+=(--topic "$TOPIC")
    [ -n "$GT" ] && args+=(--gt "$GT")
    "$BIN/iraf_vo_run" "${args[@]}" | tee "$OUT/summary_$mode.txt"
  done
  echo
  echo "== side by side ($DATASET)"
  /usr/bin/python3 - "$OUT/stats_iraf.json" "$OUT/stats_baseline.json" "$OUT/stats_clahe.json" <<'PY'
import json, sys
rows = [json.load(open(f)) for f in sys.argv[1:]]
print("%-9s %9s %6s %12s %8s %8s" % ("mode", "tracked%", "lost", "ATE rmse[m]", "fps", "CPU fps"))
for r in rows:
    ate = "%.4f" % r["ate_rmse"] if "ate_rmse" in r else "n/a"
    print("%-9s %9.1f %6d %12s %8.1f %8.1f" % (r["mode"], r["tracked_pct"], r["lost_events"], ate, r["fps"],
                                               2000.0 / r["cpu_ms_per_frame"]))
print("(fps: wall clock here; CPU fps: what the 2 cores would sustain, 2000 / CPU ms per frame)")
PY
  echo "== trajectories: $OUT/traj_iraf.txt $OUT/traj_baseline.txt $OUT/traj_clahe.txt (TUM format, evo / iraf_vo_eval readable)"
else
  echo "== enhancing $DATASET"
  "$BIN/iraf_vo_enhance" "$DATASET" "$OUT/enhanced"
fi
