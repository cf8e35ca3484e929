#!/usr/bin/env bash
# One benchmark run for speed: front-end stages and the ratio to cv::ORB (one thread, thread CPU time),
# then the whole offline VO per mode: CPU ms per frame over all threads (PNG decoding included), per-stage medians,
# local-BA runs with ms per run (wall and thread CPU) and amortised per frame, wall fps, tracked %, ATE and peak RSS.
# Speed targets live here, not in tests: the script prints the measured values next to the targets.
# Stereo (once iraf_vo_run has --stereo and the dataset has mav0/cam1): the first mode again with --stereo, and the
# stereo / mono ratio of CPU per frame (target <= 1.7) and of peak RSS.
#
#   scripts/bench.sh [--dataset ASL_DIR] [--frames N] [--frontend-frames N] [--modes "iraf baseline"] [--threaded|--sync]
#                    [--graph]
#
# --graph: also the nodelet graph (launch/dataset.launch, one manager, default parameters, the dataset's sensor.yaml)
# on a bag of the dataset played at its real rate: median / 95 % latency from each image to its odometry and the
# manager's peak RSS (scripts/graph_latency.py).
#
# Default dataset: ../shared/data/euroc_mh01_600 beside the checkout (frames 0-305, the moving part). Needs a build
# (scripts/setup.sh). Run it on an idle machine: wall-clock numbers (fps) depend on the load, CPU ms much less.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/.." && pwd)"
bin="${IRAF_VO_BUILD_DIR:-$repo/build}/devel/lib/iraf_vo"
dataset="$repo/../shared/data/euroc_mh01_600"
frames=306
fe_frames=200
modes="iraf baseline"
mapping=""
graph=0
while [[ $# -gt 0 ]]; do
  case "$1" in
    -h|--help) sed -n '2,15p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    --dataset) dataset="$2"; shift 2 ;;
    --frames) frames="$2"; shift 2 ;;
    --frontend-frames) fe_frames="$2"; shift 2 ;;
    --modes) modes="$2"; shift 2 ;;
    --threaded) mapping=""; shift ;;
    --sync) mapping="--set tracker.mapping_thread=false"; shift ;;
    --graph) graph=1; shift ;;
    *) echo "bench.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
[[ -x "$bin/iraf_vo_run" && -x "$bin/iraf_vo_bench_frontend" ]] || { echo "bench.sh: no build in $bin (run scripts/setup.sh)" >&2; exit 2; }
[[ -f "$dataset/mav0/cam0/data.csv" ]] || { echo "bench.sh: $dataset is not an ASL folder" >&2; exit 2; }
out="$(mktemp -d /tmp/iraf_vo_bench.XXXXXX)"
# Host check: on a virtual machine the hypervisor can take the CPUs away (steal time, or ticks that never reach the
# guest's accounting); then CPU and wall times are inflated and not comparable between runs. Each stage prints what
# share of (cores x wall time) the guest really had; below 90 % its numbers are marked unreliable.
cpu_snapshot() { echo "$(date +%s.%N) $(head -1 /proc/stat | cut -d' ' -f2-)"; }
host_check() {  # host_check "SNAPSHOT_BEFORE" STAGE_NAME
  /usr/bin/python3 - "$1" "$(cpu_snapshot)" "$2" "$(nproc)" "$(getconf CLK_TCK)" <<'PY'
import sys
a, b = [list(map(float, s.split())) for s in sys.argv[1:3]]
name, ncpu, hz = sys.argv[3], int(sys.argv[4]), float(sys.argv[5])
d = [y - x for x, y in zip(a, b)]
wall, ticks = d[0], d[1:]
expected = wall * ncpu * hz
steal = ticks[7] if len(ticks) > 7 else 0.0
had = sum(ticks[:7])  # user .. softirq; guest / guest_nice (after steal) are counted in user / nice already
share = 100.0 * had / expected if expected > 0 else 100.0
print("host: %s had %.0f %% of %d cores x %.1f s wall (steal %.0f %%, unaccounted %.0f %%)%s" % (
    name, share, ncpu, wall, 100.0 * steal / max(expected, 1e-9), max(0.0, 100.0 - share - 100.0 * steal / max(expected, 1e-9)),
    "" if share >= 90 else ": the hypervisor took CPU time, CPU ms and fps of this stage are UNRELIABLE (compare instruction counts, valgrind --tool=callgrind)"))
PY
}
echo "== machine: $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg); dataset $dataset"
echo "== front-end (one thread, thread CPU time, median per frame): target ratio <= 1.0 x cv::ORB(1000)"
snap="$(cpu_snapshot)"
"$bin/iraf_vo_bench_frontend" --dataset "$dataset" --frames "$fe_frames" | tee "$out/frontend.txt"
host_check "$snap" "front-end bench"
gt="$dataset/groundtruth/groundtruth_tum_cam0.txt"
[[ -f "$gt" ]] || gt="$dataset/mav0/state_groundtruth_estimate0/data.csv"
for mode in $modes; do
  echo "== whole VO, mode $mode, frames 0-$((frames - 1)) ${mapping:+(synchronous mapping)}: target <= 10 CPU ms per frame"
  args=(--dataset "$dataset" --frames "$frames" --mode "$mode" --out "$out/$mode.txt" --stats "$out/$mode.json" --quiet)
  [[ -f "$gt" ]] && args+=(--gt "$gt")
  snap="$(cpu_snapshot)"
  # shellcheck disable=SC2086
  /usr/bin/time -v "$bin/iraf_vo_run" "${args[@]}" $mapping >"$out/$mode.log" 2>"$out/$mode.time"
  host_check "$snap" "whole VO ($mode)" | tee "$out/$mode.host"
  cat "$out/$mode.log"
  /usr/bin/python3 - "$out/$mode.log" "$out/$mode.time" "$frames" "$out/frontend.txt" <<'PY'
import re, sys
log = open(sys.argv[1]).read(); tim = open(sys.argv[2]).read(); frames = int(sys.argv[3])
orb = re.search(r"cv::ORB::create\(1000\)->detectAndCompute\s+([0-9.]+)", open(sys.argv[4]).read())
cpu = re.search(r"= ([0-9.]+) ms/frame", log); ba = re.search(r"BA runs (\d+) \(mean ([0-9.]+) ms\)", log)
rss = re.search(r"Maximum resident set size \(kbytes\): (\d+)", tim)
fps = re.search(r"wall [0-9.]+ s, ([0-9.]+) fps", log)
print("summary: CPU %s ms/frame (target <= 10) | wall %s fps (target >= 150 on an idle 2-core machine)" %
      (cpu.group(1) if cpu else "?", fps.group(1) if fps else "?"))
ba_cpu = re.search(r"BA CPU ([0-9.]+) ms per run", log)
if ba:
    n, ms = int(ba.group(1)), float(ba.group(2))
    print("summary: local BA %d runs x %.1f ms wall = %.2f ms per frame amortised" % (n, ms, n * ms / max(frames, 1)))
if ba and ba_cpu:  # the mapping thread's CPU time: what the BA costs, whatever the machine's load
    cpu_ms = float(ba_cpu.group(1))
    print("summary: local BA %d runs x %.1f CPU ms = %.2f CPU ms per frame amortised" % (n, cpu_ms, n * cpu_ms / max(frames, 1)))
# The same work in units of this host's cv::ORB frame: the 10 ms target was set where cv::ORB(1000) took 4.75 ms
# per EuRoC frame (10 / 4.75 = 2.11), so hosts of different speed can be compared (the absolute target stays above).
if cpu and orb:
    print("summary: whole VO = %.2f x this host's cv::ORB(1000) frame (%.2f ms); the 10 ms target on the issue's host "
          "(cv::ORB 4.75 ms) is 2.11 x" % (float(cpu.group(1)) / float(orb.group(1)), float(orb.group(1))))
print("summary: peak RSS %.1f MiB" % (int(rss.group(1)) / 1024.0 if rss else float("nan")))
PY
done
first_mode="${modes%% *}"
if [[ -f "$dataset/mav0/cam1/data.csv" && -f "$out/$first_mode.log" ]] && grep -q -- '--stereo' <<< "$("$bin/iraf_vo_run" --help 2>&1)"; then
  echo "== whole VO stereo, mode $first_mode, frames 0-$((frames - 1)): target <= 1.7 x the mono CPU per frame"
  args=(--dataset "$dataset" --stereo --frames "$frames" --mode "$first_mode" --out "$out/stereo.txt" --stats "$out/stereo.json" --quiet)
  [[ -f "$gt" ]] && args+=(--gt "$gt")
  snap="$(cpu_snapshot)"
  # shellcheck disable=SC2086
  /usr/bin/time -v "$bin/iraf_vo_run" "${args[@]}" $mapping >"$out/stereo.log" 2>"$out/stereo.time" \
    || { echo "bench.sh: stereo run failed:"; tail -5 "$out/stereo.time"; }
  host_check "$snap" "whole VO stereo ($first_mode)"
  cat "$out/stereo.log"
  /usr/bin/python3 - "$out/$first_mode.log" "$out/$first_mode.time" "$out/stereo.log" "$out/stereo.time" <<'PY'
import re, sys
def read(log, tim):
    cpu = re.search(r"= ([0-9.]+) ms/frame", open(log).read())
    rss = re.search(r"Maximum resident set size \(kbytes\): (\d+)", open(tim).read())
    return (float(cpu.group(1)) if cpu else None), (int(rss.group(1)) / 1024.0 if rss else None)
(mc, mr), (sc, sr) = read(sys.argv[1], sys.argv[2]), read(sys.argv[3], sys.argv[4])
f = lambda v, fmt: fmt % v if v is not None else "?"
print("summary: mono %s vs stereo %s CPU ms/frame: stereo = %s x mono (target <= 1.7)" %
      (f(mc, "%.2f"), f(sc, "%.2f"), f(sc / mc if mc and sc else None, "%.2f")))
print("summary: peak RSS mono %s vs stereo %s MiB (%s x)" %
      (f(mr, "%.1f"), f(sr, "%.1f"), f(sr / mr if mr and sr else None, "%.2f")))
PY
fi
if [[ $graph == 1 ]]; then
  echo "== nodelet graph on a bag of the dataset at its real rate: image -> odometry latency, peak RSS"
  set +u  # the ROS setup scripts read unset variables
  # shellcheck disable=SC1091
  source "${IRAF_VO_BUILD_DIR:-$repo/build}/devel/setup.bash"
  set -u
  bag="$out/dataset.bag"
  "$bin/iraf_vo_asl_to_bag" "$dataset" "$bag" > "$out/bag.log" 2>&1 || { cat "$out/bag.log"; exit 1; }
  roslaunch iraf_vo dataset.launch bag:="$bag" camera_file:="$dataset/mav0/cam0/sensor.yaml" delay:=5 \
    > "$out/graph.log" 2>&1 &
  launch_pid=$!
  /usr/bin/python3 "$here/graph_latency.py" --idle 5 || echo "bench.sh: graph latency not measured (see $out/graph.log)"
  kill -INT "$launch_pid" 2>/dev/null || true
  wait "$launch_pid" 2>/dev/null || true
fi
echo "== outputs in $out"
