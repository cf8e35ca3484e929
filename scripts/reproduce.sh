#!/usr/bin/env bash
# Reproduces the evidence for iraf_vo: the ablation table (paper Tables I/II) on every sequence at hand and the
# paper's figures (Figs. 3, 4, 6, 7, 8) as PNGs. Everything runs through the same tools (iraf_vo_run etc.), so the
# modes differ only in the front-end configuration.
#
#   scripts/reproduce.sh [--out DIR] [--full] [--sim-frames N] [--euroc-frames N] [--modes "baseline he ..."]
#                        [--presets "clean dark ..."] [--no-sim] [--no-euroc] [--threaded]
#                        [--scenarios "drive slider ..."] [--scenario-modes "iraf ..."] [--scenario-frames N]
#                        [--scenario-preset clean|dark|...] [--no-scenarios]
#                        [--light-presets "night ae_hunting ..."] [--light-cameras "pinhole fisheye"] [--light-frames N]
#                        [--light-seed S] [--no-light] [--no-repeatability] [--no-stereo]
#                        [--dataset PATH [--topic T] [--gt GT] [--camera sensor.yaml]] ...
#
# Sequences (default set, ~13 min on the 2-core development machine, + ~4 min once to simulate the scenarios):
#   sim_<preset>   iraf_vo_simulate presets clean, dark, flicker, mixed, overexposed (--sim-frames, default 300)
#   euroc_*        ../shared/data/euroc_mh01_600 beside the checkout (if present), frames 0-305 (the moving part):
#                  clean and degraded with iraf_vo_degrade profiles dark and mixed (+ flicker, overexposed with --full;
#                  the profiles' events span all 600 frames, so e.g. flicker starts at frame 300)
#   sim_<light>_<camera>  the camera-model light presets night, ae_hunting, light_switch, blackout, flashlight, glare
#                  (auto-exposure, shot / read noise, gain, clipping) x --light-cameras pinhole fisheye, --light-frames
#                  (default 200), --light-seed (default 0)
#   euroc_*        also degraded with the camera-model profiles ae_hunting and night (+ the other light profiles with
#                  --full)
#   any --dataset  ASL folder or rosbag (with --topic); --gt for ATE; --camera for bags
# Repeatability (front-end consistency, iraf_vo_repeatability in every --modes mode) on each light sequence: keypoints
# of frame i re-detected in frame i+1 within 2 px of where the clean render of the same motion (EuRoC: the original
# frames) says the point went -> repeatability.md, appended to report.md (--no-repeatability skips it).
# Scenarios (other cameras and motions, iraf_vo_simulate --motion; run in --scenario-modes, default iraf only;
# each motion's default length unless --scenario-frames; photometric --scenario-preset, default clean):
#   drive                  street, KITTI-like 1241x376 pinhole, 10 Hz, ~1 m/frame, gentle turns (100 frames)
#   highway                open road, structure mostly 15-300 m away, same camera and speed, wide curves (100 frames)
#   slider                 pure sideways translation past objects at 0.3-1 m, 240x180, 25 Hz (100 frames)
#   handheld_fast          room, up to 3 deg/frame with motion blur, EuRoC pinhole 752x480, 20 Hz (300 frames)
#   handheld_fast_fisheye  the same with the TUM-VI Kannala-Brandt 512x512 camera
#   static_start           room loop after standing still for 2 s (300 frames, the first 40 static)
#   static_start_fisheye   the same with the TUM-VI Kannala-Brandt 512x512 camera
#   fisheye                the --presets (clean dark ...) with the fisheye camera (--sim-frames)
#   -> scenarios.md / scenarios.csv (tracked % after the first 5 frames of motion, first initialized frame,
#      ATE RMSE and ATE in % of the ground-truth path; pass = >= 95 % and <= 1 %), appended to report.md.
# Stereo (once iraf_vo_run has --stereo; --no-stereo skips it): scripts/stereo_table.sh in mode iraf, EuRoC 0-305
#   stereo and every simulator motion x pinhole / fisheye rendered with --stereo (seed 0): SE(3) ATE in mm and % of
#   the path, Sim(3) scale -> stereo/stereo.md, appended to report.md.
# Modes: baseline he clahe enhance adaptive culling iraf.
# Mapping runs inside the tracking thread (--set tracker.mapping_thread=false): results do not depend on the
# machine's load (deterministic up to floating point); --threaded uses the mapping thread instead.
# Output (default /tmp/iraf_vo_report): report.md, results.csv, fig*.png, runs/<seq>/<mode>.{txt,json,csv,log}.
# --full: 400 simulated frames, all four EuRoC profiles, all 600 EuRoC frames (~13 min here).
set -euo pipefail

orig_args="$*"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/.." && pwd)"
out=/tmp/iraf_vo_report
full=0
sim_frames=""
euroc_frames=""
modes="baseline he clahe enhance adaptive culling iraf"
presets="clean dark flicker mixed overexposed"
euroc_profiles="dark mixed ae_hunting night"
light_presets="night ae_hunting light_switch blackout flashlight glare"
light_cameras="pinhole fisheye"
light_frames=200
light_seed=0
do_repeat=1
do_stereo=1
do_sim=1
do_euroc=1
threaded=0
scenarios="drive highway slider handheld_fast handheld_fast_fisheye static_start static_start_fisheye fisheye"
scenario_modes="iraf"
scenario_frames=0
scenario_preset=clean
declare -a ext_paths=() ext_topics=() ext_gts=() ext_cams=()

die() { echo "reproduce.sh: $*" >&2; exit 2; }
need() { [[ $# -ge 2 && -n "$2" ]] || die "$1 needs a value"; }
while [[ $# -gt 0 ]]; do
  case "$1" in
    -h|--help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;;
    --out) need "$@"; out="$2"; shift 2 ;;
    --full) full=1; shift ;;
    --sim-frames) need "$@"; sim_frames="$2"; shift 2 ;;
    --euroc-frames) need "$@"; euroc_frames="$2"; shift 2 ;;
    --modes) need "$@"; modes="$2"; shift 2 ;;
    --presets) need "$@"; presets="$2"; shift 2 ;;
    --no-sim) do_sim=0; shift ;;
    --no-euroc) do_euroc=0; shift ;;
    --threaded) threaded=1; shift ;;
    --scenarios) need "$@"; scenarios="$2"; shift 2 ;;
    --scenario-modes) need "$@"; scenario_modes="$2"; shift 2 ;;
    --scenario-frames) need "$@"; scenario_frames="$2"; shift 2 ;;
    --scenario-preset) need "$@"; scenario_preset="$2"; shift 2 ;;
    --no-scenarios) scenarios=""; shift ;;
    --light-presets) need "$@"; light_presets="$2"; shift 2 ;;
    --light-cameras) need "$@"; light_cameras="$2"; shift 2 ;;
    --light-frames) need "$@"; light_frames="$2"; shift 2 ;;
    --light-seed) need "$@"; light_seed="$2"; shift 2 ;;
    --no-light) light_presets=""; shift ;;
    --no-repeatability) do_repeat=0; shift ;;
    --no-stereo) do_stereo=0; shift ;;
    --dataset) need "$@"; ext_paths+=("$2"); ext_topics+=(""); ext_gts+=(""); ext_cams+=(""); shift 2 ;;
    --topic|--gt|--camera)
      need "$@"; [[ ${#ext_paths[@]} -gt 0 ]] || die "$1 must follow a --dataset"
      k=$(( ${#ext_paths[@]} - 1 ))
      case "$1" in --topic) ext_topics[$k]="$2" ;; --gt) ext_gts[$k]="$2" ;; --camera) ext_cams[$k]="$2" ;; esac
      shift 2 ;;
    *) die "unknown argument '$1' (see --help)" ;;
  esac
done
if [[ -z "$euroc_frames" ]]; then euroc_frames=306; [[ $full == 1 ]] && euroc_frames=600; fi
[[ "$euroc_frames" =~ ^[0-9]+$ && "$euroc_frames" -ge 30 ]] || die "--euroc-frames '$euroc_frames': expected an integer"
if [[ -z "$sim_frames" ]]; then sim_frames=300; [[ $full == 1 ]] && sim_frames=400; fi
[[ "$sim_frames" =~ ^[0-9]+$ && "$sim_frames" -ge 60 ]] || die "--sim-frames '$sim_frames': expected an integer >= 60"
[[ $full == 1 ]] && euroc_profiles="dark mixed flicker overexposed ae_hunting night light_switch blackout flashlight glare"
[[ "$light_frames" =~ ^[0-9]+$ && "$light_frames" -ge 60 ]] || die "--light-frames '$light_frames': expected an integer >= 60"
[[ "$light_seed" =~ ^[0-9]+$ ]] || die "--light-seed '$light_seed': expected an integer >= 0"
for p in $light_presets; do
  case "$p" in night|ae_hunting|light_switch|blackout|flashlight|glare) ;; *) die "--light-presets: unknown preset '$p'" ;; esac
done
for c in $light_cameras; do
  case "$c" in pinhole|fisheye) ;; *) die "--light-cameras: unknown camera '$c'" ;; esac
done
for m in $modes $scenario_modes; do
  case "$m" in baseline|he|clahe|enhance|adaptive|culling|iraf) ;; *) die "--modes: unknown mode '$m'" ;; esac
done
for sc in $scenarios; do
  case "$sc" in drive|highway|slider|handheld_fast|handheld_fast_fisheye|static_start|static_start_fisheye|fisheye) ;;
    *) die "--scenarios: unknown scenario '$sc'" ;; esac
done
[[ "$scenario_frames" =~ ^[0-9]+$ && ( "$scenario_frames" == 0 || "$scenario_frames" -ge 30 ) ]] \
  || die "--scenario-frames '$scenario_frames': expected 0 (motion default) or an integer >= 30"
for k in "${!ext_paths[@]}"; do
  [[ -e "${ext_paths[$k]}" ]] || die "--dataset ${ext_paths[$k]}: no such file or folder"
  [[ -z "${ext_gts[$k]}" || -e "${ext_gts[$k]}" ]] || die "--gt ${ext_gts[$k]}: no such file"
done

export PATH=/usr/bin:$PATH
build="${IRAF_VO_BUILD_DIR:-$repo/build}"
bin="$build/devel/lib/iraf_vo"
tools="iraf_vo_run iraf_vo_eval iraf_vo_simulate iraf_vo_degrade iraf_vo_keypoint_curve iraf_vo_draw_keypoints
       iraf_vo_repeatability"
missing=0
for t in $tools; do [[ -x "$bin/$t" ]] || missing=1; done
if [[ $missing == 1 ]]; then
  echo "reproduce.sh: tools missing in $bin: building (scripts/setup.sh)"
  IRAF_VO_BUILD_DIR="$build" "$repo/scripts/setup.sh"
fi
for t in $tools; do [[ -x "$bin/$t" ]] || die "$bin/$t missing after the build"; done

shared="$(cd "$repo/.." && pwd)/shared/data"
euroc="$shared/euroc_mh01_600"
mkdir -p "$out/data" "$out/runs"
t_start=$(date +%s)
log() { printf '[%4ds] %s\n' $(( $(date +%s) - t_start )) "$*"; }

# ---- sequences: name|path|gt|first|frames|topic|camera ----
declare -a seqs=()
if [[ $do_sim == 1 ]]; then
  for p in $presets; do
    d="$out/data/sim_${p}_$sim_frames"
    if [[ ! -f "$d/.done" ]]; then
      log "simulating preset $p ($sim_frames frames) -> $d"
      rm -rf "$d"
      "$bin/iraf_vo_simulate" --preset "$p" --out "$d" --frames "$sim_frames" > "$out/data/sim_$p.log" 2>&1 \
        || { cat "$out/data/sim_$p.log" >&2; die "iraf_vo_simulate --preset $p failed"; }
      touch "$d/.done"
    fi
    seqs+=("sim_$p|$d|$d/groundtruth.txt|0|$sim_frames||")
  done
fi
# Light presets: name|sequence dir|clean reference dir (same motion, camera, frames, seed) for the repeatability.
declare -a light_refs=()
sim_light() {  # sim_light DIR PRESET CAMERA: renders DIR once (cached with .done)
  local d="$1" p="$2" c="$3"
  if [[ ! -f "$d/.done" ]]; then
    log "simulating preset $p, $c camera ($light_frames frames, seed $light_seed) -> $d"
    rm -rf "$d"
    "$bin/iraf_vo_simulate" --preset "$p" --camera "$c" --frames "$light_frames" --seed "$light_seed" --out "$d" \
      > "$d.log" 2>&1 || { cat "$d.log" >&2; die "iraf_vo_simulate --preset $p --camera $c failed"; }
    touch "$d/.done"
  fi
}
if [[ $do_sim == 1 ]]; then
  for c in $light_cameras; do
    [[ -n "$light_presets" ]] || break
    ref="$out/data/sim_clean_${c}_${light_frames}_s$light_seed"
    [[ $do_repeat == 1 ]] && sim_light "$ref" clean "$c"
    for p in $light_presets; do
      d="$out/data/sim_${p}_${c}_${light_frames}_s$light_seed"
      sim_light "$d" "$p" "$c"
      seqs+=("sim_${p}_$c|$d|$d/groundtruth.txt|0|$light_frames||")
      light_refs+=("sim_${p}_$c|$d|$ref|$light_frames")
    done
  done
fi
if [[ $do_euroc == 1 ]]; then
  if [[ -d "$euroc" ]]; then
    egt="$euroc/groundtruth/groundtruth_tum_cam0.txt"
    seqs+=("euroc_clean|$euroc|$egt|0|$euroc_frames||")
    for p in $euroc_profiles; do
      d="$out/data/euroc_$p"
      if [[ ! -f "$d/.done" ]]; then
        log "degrading EuRoC MH_01 with profile $p -> $d"
        rm -rf "$d"
        "$bin/iraf_vo_degrade" "$euroc" "$d" --profile "$p" > "$out/data/euroc_$p.log" 2>&1 \
          || { cat "$out/data/euroc_$p.log" >&2; die "iraf_vo_degrade --profile $p failed"; }
        touch "$d/.done"
      fi
      seqs+=("euroc_$p|$d|$d/groundtruth/groundtruth_tum_cam0.txt|0|$euroc_frames||")
      case "$p" in ae_hunting|night|light_switch|blackout|flashlight|glare) light_refs+=("euroc_$p|$d|$euroc|$euroc_frames") ;; esac
    done
  else
    log "no EuRoC frames at $euroc: skipping the EuRoC sequences"
  fi
fi
for k in "${!ext_paths[@]}"; do
  name="ext$((k + 1))_$(basename "${ext_paths[$k]}" | tr -c 'A-Za-z0-9_\n-' '_')"
  seqs+=("$name|${ext_paths[$k]}|${ext_gts[$k]}|0||${ext_topics[$k]}|${ext_cams[$k]}")
done
# ---- scenarios: other cameras and motions (iraf_vo_simulate --motion), run in --scenario-modes ----
# simulate NAME ARGS...: generates $out/data/NAME once (cached with .done), adds it to scen.
declare -a scen=()
simulate() {
  local name="$1"
  shift
  local d="$out/data/$name"
  if [[ ! -f "$d/.done" ]]; then
    log "simulating $name ($*) -> $d"
    rm -rf "$d"
    "$bin/iraf_vo_simulate" --preset "$scenario_preset" --out "$d" "$@" > "$out/data/$name.log" 2>&1 \
      || { cat "$out/data/$name.log" >&2; die "iraf_vo_simulate $* failed"; }
    touch "$d/.done"
  fi
  scen+=("$name|$d|$d/groundtruth.txt|0|||")
}
sf=()
[[ "$scenario_frames" != 0 ]] && sf=(--frames "$scenario_frames")
sp_tag="" && [[ "$scenario_preset" != clean ]] && sp_tag="_$scenario_preset"
for sc in $scenarios; do
  case "$sc" in
    drive|highway|slider|handheld_fast) simulate "sim_$sc$sp_tag" --motion "$sc" "${sf[@]}" ;;
    handheld_fast_fisheye) simulate "sim_$sc$sp_tag" --motion handheld_fast --camera fisheye "${sf[@]}" ;;
    static_start)
      ssf=$scenario_frames && [[ $ssf == 0 ]] && ssf=300
      simulate "sim_$sc$sp_tag" --motion room --static-start 2 --frames "$ssf" ;;
    static_start_fisheye)
      ssf=$scenario_frames && [[ $ssf == 0 ]] && ssf=300
      simulate "sim_$sc$sp_tag" --motion room --static-start 2 --camera fisheye --frames "$ssf" ;;
    fisheye)
      for p in $presets; do
        [[ "$p" == clean || "$p" == dark || "$p" == flicker || "$p" == mixed || "$p" == overexposed ]] || continue
        d="$out/data/sim_${p}_fisheye_$sim_frames"
        if [[ ! -f "$d/.done" ]]; then
          log "simulating preset $p with the fisheye camera ($sim_frames frames) -> $d"
          rm -rf "$d"
          "$bin/iraf_vo_simulate" --preset "$p" --camera fisheye --out "$d" --frames "$sim_frames" \
            > "$out/data/sim_${p}_fisheye.log" 2>&1 || { cat "$out/data/sim_${p}_fisheye.log" >&2; die "iraf_vo_simulate --preset $p --camera fisheye failed"; }
          touch "$d/.done"
        fi
        scen+=("sim_${p}_fisheye|$d|$d/groundtruth.txt|0|||")
      done ;;
  esac
done
[[ $(( ${#seqs[@]} + ${#scen[@]} )) -gt 0 ]] || die "no sequences to run"

# ---- runs ----
extra=()
[[ $threaded == 0 ]] && extra=(--set tracker.mapping_thread=false)
echo "mapping: $([[ $threaded == 0 ]] && echo 'synchronous (tracker.mapping_thread=false)' || echo 'threaded')" > "$out/settings.txt"
echo "sim_frames: $sim_frames" >> "$out/settings.txt"
echo "scenarios: ${scenarios:-none} (modes: $scenario_modes, frames: $([[ $scenario_frames == 0 ]] && echo 'motion default' || echo "$scenario_frames"), photometric preset: $scenario_preset)" >> "$out/settings.txt"
echo "euroc_frames: $euroc_frames" >> "$out/settings.txt"
echo "machine: $(nproc) cores, $(uname -m), load at start: $(cut -d' ' -f1-3 /proc/loadavg)" >> "$out/settings.txt"
echo "command: scripts/reproduce.sh $orig_args" >> "$out/settings.txt"
: > "$out/index.csv"
echo "sequence,mode,path,gt,traj,stats,eval_json,errors_csv,first,frames,wall_s" > "$out/index.csv"
n_modes=$(wc -w <<< "$modes")
n_seq=${#seqs[@]}
total=$(( n_seq * n_modes + ${#scen[@]} * $(wc -w <<< "$scenario_modes") ))
echo "sequence,mode,path,gt,traj,stats,eval_json,errors_csv,first,frames,wall_s" > "$out/scenarios.csv"
run_i=0
# run_one INDEX_CSV NAME PATH GT FIRST FRAMES TOPIC CAMERA MODE: one iraf_vo_run (+ iraf_vo_eval) -> index row.
run_one() {
  local index="$1" name="$2" path="$3" gt="$4" first="$5" frames="$6" topic="$7" cam="$8" m="$9"
  mkdir -p "$out/runs/$name"
  run_i=$((run_i + 1))
  local r="$out/runs/$name/$m"
  local args=(--dataset "$path" --out "$r.txt" --stats "$r.json" --mode "$m" --quiet --first "$first"
              --frame-log "$r.frames.csv")
  [[ -n "$frames" ]] && args+=(--frames "$frames")
  [[ -n "$topic" ]] && args+=(--topic "$topic")
  [[ -n "$cam" ]] && args+=(--camera "$cam")
  [[ -n "$gt" ]] && args+=(--gt "$gt")
  printf '[%4ds] run %d/%d  sequence %s  mode %-8s ... ' $(( $(date +%s) - t_start )) "$run_i" "$total" "$name" "$m"
  local t0
  t0=$(date +%s%N)
  if ! "$bin/iraf_vo_run" "${args[@]}" "${extra[@]}" > "$r.log" 2>&1; then
    echo "FAILED (see $r.log)"
    return 0
  fi
  local wall_ms=$(( ($(date +%s%N) - t0) / 1000000 ))
  local wall
  wall=$(printf '%d.%03d' $((wall_ms / 1000)) $((wall_ms % 1000)))
  local ej="" ec=""
  if [[ -n "$gt" && -s "$r.txt" ]]; then
    local camargs=()
    if [[ -n "$cam" ]]; then camargs=(--camera "$cam")
    elif [[ -f "$path/mav0/cam0/sensor.yaml" ]]; then camargs=(--camera "$path/mav0/cam0/sensor.yaml"); fi
    if "$bin/iraf_vo_eval" "$gt" "$r.txt" --align sim3 --json "$r.eval.json" --csv "$r.errors.csv" "${camargs[@]}" \
         > "$r.eval.log" 2>&1; then
      ej="$r.eval.json" ec="$r.errors.csv"
    fi
  fi
  echo "$name,$m,$path,$gt,$r.txt,$r.json,$ej,$ec,$first,$frames,$wall" >> "$index"
  python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); print("tracked %.1f %%, lost %d, ATE %s, %.1f ms/frame CPU, %ss wall" % (d["tracked_pct"], d["lost_events"], ("%.4f m" % d["ate_rmse"]) if "ate_rmse" in d else "-", d["cpu_ms_per_frame"], sys.argv[2]))' "$r.json" "$(printf '%.0f' "$wall")" \
    || echo "done"
}
for s in "${seqs[@]}"; do
  IFS='|' read -r name path gt first frames topic cam <<< "$s"
  for m in $modes; do run_one "$out/index.csv" "$name" "$path" "$gt" "$first" "$frames" "$topic" "$cam" "$m"; done
done
for s in "${scen[@]}"; do
  IFS='|' read -r name path gt first frames topic cam <<< "$s"
  for m in $scenario_modes; do run_one "$out/scenarios.csv" "$name" "$path" "$gt" 0 "" "" "" "$m"; done
done

# ---- repeatability of the front-end on the light sequences (iraf_vo_repeatability, every --modes mode) ----
rm -f "$out/repeatability.md"
if [[ $do_repeat == 1 && ${#light_refs[@]} -gt 0 ]]; then
  {
    echo
    echo "## Front-end repeatability on the light sequences"
    echo
    echo "Keypoints of frame i re-detected in frame i+1 within 2 px (and +-1 pyramid level) of where the clean"
    echo "reference (the clean render of the same motion; EuRoC: the original frames) says the point went"
    echo "(iraf_vo_repeatability, pooled over the pairs; p10 = 10th percentile over the pairs; matched = true"
    echo "matches with descriptor distance <= 50; hamming = mean descriptor distance of the true matches)."
    echo
    echo "| sequence | mode | keypoints | repeatability | p10 | matched | hamming |"
    echo "|---|---|---|---|---|---|---|"
  } > "$out/repeatability.md"
  for s in "${light_refs[@]}"; do
    IFS='|' read -r name path ref frames <<< "$s"
    log "repeatability of $name (reference $ref)"
    mkdir -p "$out/runs/$name"
    if "$bin/iraf_vo_repeatability" --dataset "$path" --reference "$ref" --frames "$frames" --modes "$modes" \
         --csv "$out/runs/$name/repeatability.csv" > "$out/runs/$name/repeatability.txt" 2>&1; then
      awk -v n="$name" 'NR > 2 { printf "| %s | %s | %s | %s | %s | %s | %s |\n", n, $1, $2, $3, $4, $5, $6 }' \
        "$out/runs/$name/repeatability.txt" >> "$out/repeatability.md"
    else
      log "iraf_vo_repeatability failed on $name (see $out/runs/$name/repeatability.txt)"
    fi
  done
fi

# ---- figure inputs ----
if [[ -d "$shared/lowlight_stills" ]]; then
  log "keypoint curve on $shared/lowlight_stills (Fig. 3)"
  "$bin/iraf_vo_keypoint_curve" --input "$shared/lowlight_stills" --output "$out/keypoint_curve.csv" > "$out/keypoint_curve.log" 2>&1 \
    || { log "iraf_vo_keypoint_curve failed (see $out/keypoint_curve.log)"; rm -f "$out/keypoint_curve.csv"; }
else
  log "no low-light stills at $shared/lowlight_stills: Fig. 3 skipped"
  rm -f "$out/keypoint_curve.csv"
fi
# Fig. 4: the darkest frame of each dark sequence at hand (real EuRoC, simulated, --dataset folders):
# baseline vs IRAF keypoints side by side, fig4_keypoints_<sequence>.png.
rm -f "$out"/fig4_keypoints_*.png
n_fig4=0
for cand in "euroc_dark|$out/data/euroc_dark" "sim_dark|$out/data/sim_dark_$sim_frames"; do
  IFS='|' read -r fname fdir <<< "$cand"
  [[ -f "$fdir/mav0/cam0/data.csv" ]] || continue
  dark_img=$(python3 "$here/report.py" --darkest "$fdir" --max-frames "$euroc_frames") || continue
  log "keypoints on the darkest frame of $fname: $dark_img (Fig. 4)"
  if "$bin/iraf_vo_draw_keypoints" --input "$dark_img" --output "$out/fig4_keypoints_$fname.png" > "$out/fig4_$fname.log" 2>&1; then
    sed 's/^/    /' "$out/fig4_$fname.log"
    n_fig4=$((n_fig4 + 1))
  else
    log "iraf_vo_draw_keypoints failed (see $out/fig4_$fname.log)"
  fi
done
for k in "${!ext_paths[@]}"; do
  [[ $n_fig4 == 0 && -f "${ext_paths[$k]}/mav0/cam0/data.csv" ]] || continue
  dark_img=$(python3 "$here/report.py" --darkest "${ext_paths[$k]}" --max-frames 0) || continue
  log "keypoints on the darkest frame of ${ext_paths[$k]}: $dark_img (Fig. 4)"
  "$bin/iraf_vo_draw_keypoints" --input "$dark_img" --output "$out/fig4_keypoints_ext$((k + 1)).png" > "$out/fig4_ext.log" 2>&1 \
    && n_fig4=1 || log "iraf_vo_draw_keypoints failed (see $out/fig4_ext.log)"
done
[[ $n_fig4 -gt 0 ]] || log "no dark sequence: Fig. 4 skipped"

log "writing the report"
if [[ ${#seqs[@]} -gt 0 ]]; then
  python3 "$here/report.py" --out "$out"
else
  : > "$out/report.md"
fi
if [[ ${#scen[@]} -gt 0 ]]; then
  python3 "$here/sim_scenarios.py" --out "$out"
  cat "$out/scenarios.md" >> "$out/report.md"
fi
[[ -f "$out/repeatability.md" ]] && cat "$out/repeatability.md" >> "$out/report.md"
if [[ $do_stereo == 1 ]]; then
  if grep -q -- '--stereo' <<< "$("$bin/iraf_vo_run" --help 2>&1)"; then
    log "stereo table (scripts/stereo_table.sh)"
    stereo_args=(--out "$out/stereo")
    [[ $do_euroc == 1 ]] || stereo_args+=(--no-euroc)
    [[ $do_sim == 1 ]] || stereo_args+=(--no-sim)
    [[ $threaded == 1 ]] && stereo_args+=(--threaded)
    IRAF_VO_BUILD_DIR="$build" "$here/stereo_table.sh" "${stereo_args[@]}" && cat "$out/stereo/stereo.md" >> "$out/report.md" \
      || log "stereo table failed (see above)"
  else
    log "iraf_vo_run has no --stereo: stereo table skipped"
  fi
fi
log "done: $out/report.md"
