#!/usr/bin/env bash
# The light-preset table: every light preset x camera x seed, VO in each front-end mode (default settings:
# threaded mapping unless --sync), and the done rule per sequence: iraf ATE <= 1.1 x the best of
# baseline / he / clahe, no lost event where the baseline has none, and on night and flashlight iraf <= 0.5 x baseline.
#
#   scripts/light_table.sh [--out DIR] [--sims DIR] [--bin DIR] [--frames N] [--seeds "0 11"]
#                          [--presets "night ae_hunting ..."] [--cameras "pinhole fisheye"]
#                          [--modes "iraf baseline he clahe"] [--sync] [--euroc DIR [--euroc-seeds "1"]]
#                          [--no-sims] [--stereo] [-- iraf_vo_run args]
#
# --euroc DIR: also the real EuRoC frames 0-305 of DIR (ASL, with groundtruth/groundtruth_tum_cam0.txt) passed
# through the camera model with each preset as an iraf_vo_degrade profile (--seed per --euroc-seeds; cached in
# the --sims folder as euroc_P_sS); rows with camera "euroc". --no-sims: only those rows.
# --sims: where the simulated sequences are cached (DIR/P_C_sS, rendered once with iraf_vo_simulate --threads 1;
# default OUT/sims). --bin: folder with iraf_vo_run / iraf_vo_simulate (default: this checkout's build).
# --sync: --set tracker.mapping_thread=false (deterministic up to floating point).
# --stereo: stereo VO (iraf_vo_run --stereo) on stereo renders of the sims (cached as P_C_sS_stereo) and on the
# EuRoC copies' cam1 (frames 0-305 all have one); the table compares the SE(3) ATE and adds the metric check:
# iraf within 0.5 % of the path and its Sim(3) scale within 1 % of 1.
# Output: OUT/results.csv (preset,camera,seed,mode,ate_mm,lost_events,resets,tracked,frames,se3_mm,scale,path_m)
# and OUT/table.md (printed): ATE [mm] (lost events) per sequence and mode (Sim(3); SE(3) with --stereo), iraf /
# best other, the rule's verdict.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/.." && pwd)"
out=/tmp/iraf_vo_light_table
sims=""
bin="${IRAF_VO_BUILD_DIR:-$repo/build}/devel/lib/iraf_vo"
frames=200
seeds="0 11"
presets="night ae_hunting light_switch blackout flashlight glare"
cameras="pinhole fisheye"
modes="iraf baseline he clahe"
euroc=""
euroc_seeds="1"
with_sims=1
stereo=0
declare -a extra=()
die() { echo "light_table.sh: $*" >&2; exit 2; }
need() { [[ $# -ge 2 && -n "$2" ]] || die "$1 needs a value"; }
while [[ $# -gt 0 ]]; do
  case "$1" in
    -h|--help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;;
    --out) need "$@"; out="$2"; shift 2 ;;
    --sims) need "$@"; sims="$2"; shift 2 ;;
    --bin) need "$@"; bin="$2"; shift 2 ;;
    --frames) need "$@"; frames="$2"; shift 2 ;;
    --seeds) need "$@"; seeds="$2"; shift 2 ;;
    --presets) need "$@"; presets="$2"; shift 2 ;;
    --cameras) need "$@"; cameras="$2"; shift 2 ;;
    --modes) need "$@"; modes="$2"; shift 2 ;;
    --euroc) need "$@"; euroc="$2"; shift 2 ;;
    --euroc-seeds) need "$@"; euroc_seeds="$2"; shift 2 ;;
    --no-sims) with_sims=0; shift ;;
    --stereo) stereo=1; shift ;;
    --sync) extra+=(--set tracker.mapping_thread=false); shift ;;
    --) shift; extra+=("$@"); break ;;
    *) die "unknown argument '$1' (see --help)" ;;
  esac
done
[[ "$frames" =~ ^[0-9]+$ && "$frames" -ge 60 ]] || die "--frames '$frames': expected an integer >= 60"
for p in $presets; do
  case "$p" in night|ae_hunting|light_switch|blackout|flashlight|glare) ;; *) die "--presets: unknown preset '$p'" ;; esac
done
for c in $cameras; do case "$c" in pinhole|fisheye) ;; *) die "--cameras: unknown camera '$c'" ;; esac; done
for s in $seeds $euroc_seeds; do [[ "$s" =~ ^[0-9]+$ ]] || die "--seeds / --euroc-seeds: '$s' is not an integer"; done
if [[ -n "$euroc" ]]; then
  [[ -f "$euroc/mav0/cam0/data.csv" ]] || die "--euroc $euroc: not an ASL sequence (no mav0/cam0/data.csv)"
  [[ -f "$euroc/groundtruth/groundtruth_tum_cam0.txt" ]] || die "--euroc $euroc: no groundtruth/groundtruth_tum_cam0.txt"
fi
for m in $modes; do
  case "$m" in baseline|he|clahe|enhance|adaptive|culling|iraf) ;; *) die "--modes: unknown mode '$m'" ;; esac
done
for t in iraf_vo_run iraf_vo_simulate iraf_vo_degrade; do [[ -x "$bin/$t" ]] || die "$bin/$t missing (build first: scripts/setup.sh)"; done
[[ -n "$sims" ]] || sims="$out/sims"
export PATH=/usr/bin:$PATH
mkdir -p "$out/runs" "$sims"
csv="$out/results.csv"
echo "preset,camera,seed,mode,ate_mm,lost_events,resets,tracked,frames,se3_mm,scale,path_m" > "$csv"
declare -a vo_args=()
[[ $stereo == 0 ]] || vo_args=(--stereo)
t0=$(date +%s)
log() { printf '[%4ds] %s\n' $(( $(date +%s) - t0 )) "$*" >&2; }

# run_modes PRESET CAMERA SEED DATASET GT [iraf_vo_run args]: one row per mode into results.csv.
run_modes() {
  local p="$1" c="$2" s="$3" d="$4" gt="$5" m r
  shift 5
  for m in $modes; do
    r="$out/runs/${p}_${c}_s$s.$m"
    "$bin/iraf_vo_run" --dataset "$d" --mode "$m" --gt "$gt" --out "$r.txt" --stats "$r.json" "$@" \
      ${vo_args[@]+"${vo_args[@]}"} ${extra[@]+"${extra[@]}"} > "$r.log" 2>&1 \
      || { log "iraf_vo_run failed on $p $c seed $s $m (see $r.log)"; continue; }
    /usr/bin/python3 - "$r.json" "$r.log" "$p" "$c" "$s" "$m" >> "$csv" <<'EOF'
import json, re, sys
j = json.load(open(sys.argv[1]))
path = re.search(r"GT path ([0-9.]+) m", open(sys.argv[2]).read())
mm = lambda key: "%.1f" % (1000 * j[key]) if j.get(key) is not None else "nan"
print(",".join(sys.argv[3:7] + [mm("ate_rmse"), str(j["lost_events"]), str(j["resets"]), str(j["tracked"]),
                                 str(j["frames"]), mm("ate_se3_rmse"), "%.5f" % j.get("ate_scale", float("nan")),
                                 path.group(1) if path else "nan"]))
EOF
    log "$p $c seed $s $m: $(tail -1 "$csv")"
  done
}

if [[ $with_sims == 1 ]]; then
  for s in $seeds; do
    for c in $cameras; do
      for p in $presets; do
        d="$sims/${p}_${c}_s$s"
        [[ $frames == 200 ]] || d="${d}_f$frames"
        [[ $stereo == 0 ]] || d="${d}_stereo"
        if [[ ! -f "$d.done" ]]; then
          log "simulating $p, $c, seed $s -> $d"
          rm -rf "$d"
          "$bin/iraf_vo_simulate" --preset "$p" --camera "$c" --frames "$frames" --seed "$s" --threads 1 --out "$d" \
            ${vo_args[@]+"${vo_args[@]}"} > "$d.log" 2>&1 || { cat "$d.log" >&2; die "iraf_vo_simulate --preset $p --camera $c --seed $s failed"; }
          touch "$d.done"
        fi
        run_modes "$p" "$c" "$s" "$d" "$d/groundtruth.txt"
      done
    done
  done
fi
if [[ -n "$euroc" ]]; then
  for s in $euroc_seeds; do
    for p in $presets; do
      d="$sims/euroc_${p}_s$s"
      if [[ ! -f "$d.done" ]]; then
        log "degrading $euroc with $p, seed $s -> $d"
        rm -rf "$d"
        "$bin/iraf_vo_degrade" "$euroc" "$d" --profile "$p" --seed "$s" > "$d.log" 2>&1 \
          || { cat "$d.log" >&2; die "iraf_vo_degrade --profile $p --seed $s failed"; }
        touch "$d.done"
      fi
      run_modes "$p" euroc "$s" "$d" "$euroc/groundtruth/groundtruth_tum_cam0.txt" --frames 306
    done
  done
fi

/usr/bin/python3 - "$csv" "$stereo" > "$out/table.md" <<'EOF'
import csv, collections, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
stereo = sys.argv[2] == "1"
key = "se3_mm" if stereo else "ate_mm"  # stereo: the metric (SE(3)-aligned) ATE
seqs = collections.OrderedDict()
for r in rows:
    seqs.setdefault((r["preset"], r["camera"], r["seed"]), {})[r["mode"]] = r
modes = []
for r in rows:
    if r["mode"] not in modes:
        modes.append(r["mode"])
print("| sequence | " + " | ".join(modes) + " | iraf / best other | iraf / baseline | rule |" +
      (" iraf % of path / scale | metric |" if stereo else ""))
print("|---|" + "---|" * (len(modes) + 3 + (2 if stereo else 0)))
ok = total = metric_ok = 0
for (p, c, s), by in seqs.items():
    cell = lambda m: "%s (%s)" % (by[m][key], by[m]["lost_events"]) if m in by else "-"
    line = "| %s, %s, seed %s | " % (p, c, s) + " | ".join(cell(m) for m in modes)
    ate = lambda m: float(by[m][key]) if m in by else math.nan
    others = [ate(m) for m in ("baseline", "he", "clahe") if m in by and not math.isnan(ate(m))]
    verdict = "-"
    rel = rel_base = math.nan
    if "iraf" in by and others:
        rel = ate("iraf") / min(others)
        rel_base = ate("iraf") / ate("baseline") if "baseline" in by else math.nan
        extra_lost = "baseline" in by and int(by["iraf"]["lost_events"]) > 0 and int(by["baseline"]["lost_events"]) == 0
        good = rel <= 1.1 and not extra_lost
        if p in ("night", "flashlight"):
            good = good and rel_base <= 0.5
        verdict = "yes" if good else "**no**"
        ok += good
        total += 1
    metric = ""
    if stereo and "iraf" in by:
        pct = 0.1 * ate("iraf") / float(by["iraf"]["path_m"])
        scale = float(by["iraf"]["scale"])
        good_metric = pct <= 0.5 and abs(scale - 1.0) <= 0.01
        metric_ok += good_metric
        metric = " %.3f %% / %.4f | %s |" % (pct, scale, "yes" if good_metric else "**no**")
    print(line + " | %.2f | %.2f | %s |" % (rel, rel_base, verdict) + metric)
print()
print("rule holds on %d of %d sequences" % (ok, total))
if stereo:
    print("metric (iraf SE(3) ATE <= 0.5 %% of the path, scale within 1 %%) on %d of %d sequences" % (metric_ok, total))
EOF
cat "$out/table.md"
