#!/usr/bin/env bash
# Repeats iraf_vo_run N times on one sequence and prints the Sim(3) ATE RMSE of every run, the median, the
# max, max/median and the number of "collapses" (ATE > 5x the median, or lost / reset runs). Used to check
# that threaded mapping is reproducible.
#
# usage: scripts/repeat_runs.sh [-n RUNS] [-j PARALLEL] [-b BIN_DIR] [-o OUT_DIR] SEQUENCE [-- iraf_vo_run args]
#   SEQUENCE: euroc (= ../shared/data/euroc_mh01_600, frames 0-305, cam0 ground truth), euroc:DIR (an
#             iraf_vo_degrade copy of it, frames 0-305, the same ground truth) or a simulator output folder
#             (iraf_vo_simulate --out DIR; ground truth DIR/groundtruth.txt)
#   -b BIN_DIR: folder with iraf_vo_run (default: build/devel/lib/iraf_vo of this checkout); a copied binary can
#             be used with its libraries through LD_LIBRARY_PATH (RUNPATH)
#   extra args after --, e.g. -- --set tracker.mapping_thread=false --mode baseline
# Output lines: "run K ate=... tracked=... lost=... resets=... kf=..." then "SUMMARY seq median max ratio collapses".
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
runs=10 par=1 bin="$here/build/devel/lib/iraf_vo" out=""
while getopts "n:j:b:o:" opt; do
  case $opt in
    n) runs=$OPTARG ;; j) par=$OPTARG ;; b) bin=$OPTARG ;; o) out=$OPTARG ;;
    *) sed -n 2,12p "$0"; exit 2 ;;
  esac
done
shift $((OPTIND - 1))
[ $# -ge 1 ] || { sed -n 2,12p "$0"; exit 2; }
seq_arg=$1; shift
[ "${1:-}" = "--" ] && shift
if [ "$seq_arg" = euroc ] || [[ "$seq_arg" == euroc:* ]]; then
  ds="${seq_arg#euroc:}"
  if [ "$ds" = euroc ]; then
    ds="$here/../shared/data/euroc_mh01_600"
    [ -d "$ds" ] || ds=/work/shared/data/euroc_mh01_600
  fi
  gt="$ds/groundtruth/groundtruth_tum_cam0.txt"
  [ -f "$gt" ] || gt="$here/../shared/data/euroc_mh01_600/groundtruth/groundtruth_tum_cam0.txt"
  seq_args=(--dataset "$ds" --gt "$gt" --frames 306)
  name=euroc
  [ "$seq_arg" = euroc ] || name=$(basename "$ds")
else
  seq_args=(--dataset "$seq_arg" --gt "$seq_arg/groundtruth.txt")
  name=$(basename "$seq_arg")
fi
[ -n "$out" ] || out=$(mktemp -d /tmp/repeat_runs.XXXXXX)
mkdir -p "$out"
one() {
  local k=$1; shift
  "$bin/iraf_vo_run" "${seq_args[@]}" --mode iraf --out "$out/$name.$k.traj.txt" --stats "$out/$name.$k.json" \
    --frame-log "$out/$name.$k.frames.csv" --quiet "$@" >"$out/$name.$k.log" 2>&1 || true
}
for ((k = 0; k < runs; k++)); do
  one "$k" "$@" &
  while [ "$(jobs -rp | wc -l)" -ge "$par" ]; do wait -n || true; done
done
wait
/usr/bin/python3 - "$out" "$name" "$runs" <<'EOF'
import json, statistics, sys
out, name, runs = sys.argv[1], sys.argv[2], int(sys.argv[3])
ates, bad = [], 0
for k in range(runs):
    try:
        s = json.load(open(f"{out}/{name}.{k}.json"))
    except Exception as e:
        print(f"run {k} FAILED ({e})"); bad += 1; continue
    a = s.get("ate_rmse", float("nan"))
    print(f"run {k} ate={a:.4f} tracked={s['tracked_pct']:.1f} lost={s['lost_events']} resets={s['resets']} kf={s['keyframes']}")
    ates.append(a)
    bad += s["lost_events"] > 0 or s["resets"] > 0
med = statistics.median(ates) if ates else float("nan")
mx = max(ates) if ates else float("nan")
coll = sum(a > 5 * med for a in ates)
print(f"SUMMARY {name} runs={len(ates)} median={med:.4f} max={mx:.4f} max/median={mx / med:.2f} "
      f"collapses(>5x median)={coll} lost_or_reset_runs={bad} out={out}")
EOF
