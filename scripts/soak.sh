#!/usr/bin/env bash
# Soak test of the offline runner: renders a short synthetic sequence (iraf_vo_simulate), loops it
# forwards/backwards (ping-pong, so the motion stays continuous) into an ASL folder of --frames rows that reuse
# the rendered images, runs iraf_vo_run over it and samples its RSS (VmRSS) once per second.
# Reports the RSS after warm-up (first sample past --warmup frames) and at the end; a steady growth
# between the two suggests a leak / unbounded map. Exits non-zero if iraf_vo_run fails.
#
# Usage: scripts/soak.sh [--frames 10000] [--source-frames 300] [--warmup 1000] [--width 376 --height 240]
#                        [--mode iraf] [--work DIR]
# Needs a built tree: IRAF_VO_BUILD_DIR (default build/) with devel/lib/iraf_vo/{iraf_vo_simulate,iraf_vo_run}.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${IRAF_VO_BUILD_DIR:-$ROOT/build}"
BIN="$BUILD_DIR/devel/lib/iraf_vo"
FRAMES=10000 SOURCE=300 WARMUP=1000 WIDTH=376 HEIGHT=240 MODE=iraf WORK=""
while [ $# -gt 0 ]; do
  case "$1" in
    --frames) FRAMES="$2"; shift ;;
    --source-frames) SOURCE="$2"; shift ;;
    --warmup) WARMUP="$2"; shift ;;
    --width) WIDTH="$2"; shift ;;
    --height) HEIGHT="$2"; shift ;;
    --mode) MODE="$2"; shift ;;
    --work) WORK="$2"; shift ;;
    -h|--help) sed -n '2,11p' "$0"; exit 0 ;;
    *) echo "soak.sh: unknown argument '$1'" >&2; exit 2 ;;
  esac
  shift
done
for t in iraf_vo_simulate iraf_vo_run; do
  [ -x "$BIN/$t" ] || { echo "soak.sh: $BIN/$t not built (scripts/setup.sh)" >&2; exit 1; }
done
if [ -z "$WORK" ]; then WORK="$(mktemp -d /tmp/iraf_vo_soak.XXXXXX)"; fi
mkdir -p "$WORK"

echo "soak.sh: rendering $SOURCE frames ${WIDTH}x${HEIGHT} into $WORK/src"
"$BIN/iraf_vo_simulate" --preset clean --out "$WORK/src" --frames "$SOURCE" --width "$WIDTH" --height "$HEIGHT" \
  --threads 0 >"$WORK/simulate.log" 2>&1 || { cat "$WORK/simulate.log"; exit 1; }

# Looped ASL folder: data/ is a symlink to the rendered images, data.csv has FRAMES rows at 20 Hz.
LOOP="$WORK/loop/mav0/cam0"
mkdir -p "$LOOP"
ln -sfn "$WORK/src/mav0/cam0/data" "$LOOP/data"
cp "$WORK/src/mav0/cam0/sensor.yaml" "$LOOP/sensor.yaml"
mapfile -t names < <(grep -v '^#' "$WORK/src/mav0/cam0/data.csv" | cut -d, -f2 | tr -d ' \r')
n=${#names[@]}
[ "$n" -ge 2 ] || { echo "soak.sh: the simulator wrote $n frames" >&2; exit 1; }
awk -v N="$FRAMES" -v n="$n" -v list="${names[*]}" 'BEGIN {
  split(list, f, " "); print "#timestamp [ns],filename"; period = 2 * (n - 1);
  for (i = 0; i < N; ++i) { k = i % period; if (k >= n) k = period - k; printf "%.0f,%s\n", 1000000000000000000 + i * 50000000, f[k + 1] }
}' >"$LOOP/data.csv"

echo "soak.sh: iraf_vo_run over $FRAMES frames (mode $MODE), RSS samples in $WORK/rss.csv"
"$BIN/iraf_vo_run" --dataset "$WORK/loop" --out "$WORK/traj.txt" --mode "$MODE" --stats "$WORK/stats.json" \
  >"$WORK/run.out" 2>"$WORK/run.err" &
pid=$!
echo "t_s,frames,rss_kb" >"$WORK/rss.csv"
t0=$(date +%s)
while kill -0 "$pid" 2>/dev/null; do
  rss=$(awk '/^VmRSS/ {print $2}' /proc/$pid/status 2>/dev/null || true)
  fr=$(grep -o '[0-9]*/[0-9]* frames' "$WORK/run.err" 2>/dev/null | tail -1 | cut -d/ -f1 || true)
  [ -n "$rss" ] && echo "$(( $(date +%s) - t0 )),${fr:-0},$rss" >>"$WORK/rss.csv"
  sleep 1
done
rc=0
wait "$pid" || rc=$?
cat "$WORK/run.out"
if [ "$rc" != 0 ]; then echo "soak.sh: iraf_vo_run failed (exit $rc):" >&2; tail -20 "$WORK/run.err" >&2; exit 1; fi
awk -F, -v W="$WARMUP" 'NR > 1 { if (!w && $2 >= W) { w = $3; wf = $2; wt = $1 } last = $3; lf = $2; lt = $1; if ($3 > mx) mx = $3 }
  END { if (!w) { w = last; wf = lf; wt = lt }
        printf "soak.sh: RSS after warm-up %.1f MB (frame %d, %d s); at the end %.1f MB (frame %d, %d s); peak %.1f MB; growth %+.1f MB\n",
               w / 1024, wf, wt, last / 1024, lf, lt, mx / 1024, (last - w) / 1024 }' "$WORK/rss.csv"
