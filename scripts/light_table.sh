#!/usr/bin/env bash
# The light-preset table: every light preset x camera x seed, VO in each front-end mode (default settings:
# threaded mapping unless --sync), and the done rule per sequence: iraf ATE <= 1.1 x the best of
# baseline / he / clahe, no lost event where the baseline has none, and on night and flashlight iraf <= 0.5 x baseline.
#
#   scripts/light_table.sh [--out DIR] [--sims DIR] [--bin DIR] [--frames N] [--seeds "0 11"]
#                          [--presets "night ae_hunting ..."] [--cameras "pinhole fisheye"]
#                          [--modes "iraf baseline he clahe"] [--sync] [--euroc DIR [--euroc-seeds "1"]]
#                          [--no-sims] [--stereo] [--draws "-20 0 20"] [--reference DIR] [-- iraf_vo_run args]
#
# --draws OFFSETS: run every mode once per offset, with features.n_features = the resolution rule's value for that
# camera + offset (0 = the default run), and judge the rule on each mode's geometric mean ATE over the draws (lost
# events summed). A single run sits anywhere within the spread that small changes cause (on the 200-frame sims the
# same front-end gives 10-40 % different ATEs for n_features 20 apart): the draws tell a systematic difference from
# a lucky or unlucky draw; the table's "single draws" column says on how many of the draws alone the rule holds
# (0 of 3: a systematic loss; 2 of 3: within the spread). Distinct offsets; default "0" (one default run per mode).
#
# --reference DIR: an earlier table's output folder (same sims, frames, draws): the modes not in --modes are taken
# from DIR/results.csv instead of being run, and the table is followed by the comparison with DIR's table on the same
# sequences (iraf's ATE and the rule's verdict per sequence that changed, the pass count, iraf's geometric mean over
# the runs). A change of the IRAF front-end then costs one mode's runs: --modes iraf --reference DIR.
# --euroc DIR: also the real EuRoC frames 0-305 of DIR (ASL, with groundtruth/groundtruth_tum_cam0.txt) passed
# through the camera model with each preset as an iraf_vo_degrade profile (--seed per --euroc-seeds; cached in
# the --sims folder as euroc_P_sS); rows with camera "euroc". --no-sims: only those rows.
# --sims: where the simulated sequences are cached (DIR/P_C_sS, rendered once with iraf_vo_simulate --threads 1;
# default OUT/sims). --bin: folder with iraf_vo_run / iraf_vo_simulate (default: this checkout's build).
# --sync: --set tracker.mapping_thread=false (deterministic up to floating point).
# --stereo: stereo VO (iraf_vo_run --stereo) on stereo renders of the sims (cached as P_C_sS_stereo) and on the
# EuRoC copies' cam1 (frames 0-305 all have one); the table compares the SE(3) ATE and adds the metric check:
# iraf within 0.5 % of the path and its Sim(3) scale within 1 % of 1.
# Output: OUT/results.csv (preset,camera,seed,mode,ate_mm,lost_events,resets,tracked,frames,se3_mm,scale,path_m,draw;
# ATEs in mm to 0.01)
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
draws="0"
reference=""
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
    --draws) need "$@"; draws="$2"; shift 2 ;;
    --reference) need "$@"; reference="$2"; shift 2 ;;
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
for k in $draws; do [[ "$k" =~ ^-?[0-9]+$ ]] || die "--draws: '$k' is not an integer"; done
[[ -n "${draws// /}" ]] || die "--draws: no offset given"
dup=$(tr ' ' '\n' <<< "$draws" | grep -v '^$' | sed 's/^-0$/0/; s/^\(-\?\)0*\([0-9]\)/\1\2/' | sort | uniq -d | head -1)
[[ -z "$dup" ]] || die "--draws: offset $dup given twice (each offset is one run per mode)"
if [[ -n "$euroc" ]]; then
  [[ -f "$euroc/mav0/cam0/data.csv" ]] || die "--euroc $euroc: not an ASL sequence (no mav0/cam0/data.csv)"
  [[ -f "$euroc/groundtruth/groundtruth_tum_cam0.txt" ]] || die "--euroc $euroc: no groundtruth/groundtruth_tum_cam0.txt"
fi
for m in $modes; do
  case "$m" in baseline|he|clahe|enhance|adaptive|culling|iraf) ;; *) die "--modes: unknown mode '$m'" ;; esac
done
[[ -z "$reference" || -f "$reference/results.csv" ]] || die "--reference $reference: no results.csv there"
[[ -z "$reference" || "$(cd "$reference" && pwd)" != "$(mkdir -p "$out" && cd "$out" && pwd)" ]] \
  || die "--reference: the same folder as --out (its results.csv is rewritten)"
for t in iraf_vo_run iraf_vo_simulate iraf_vo_degrade; do [[ -x "$bin/$t" ]] || die "$bin/$t missing (build first: scripts/setup.sh)"; done
[[ -n "$sims" ]] || sims="$out/sims"
export PATH=/usr/bin:$PATH
mkdir -p "$out/runs" "$sims"
csv="$out/results.csv"
echo "preset,camera,seed,mode,ate_mm,lost_events,resets,tracked,frames,se3_mm,scale,path_m,draw" > "$csv"
declare -a vo_args=()
[[ $stereo == 0 ]] || vo_args=(--stereo)
t0=$(date +%s)
log() { printf '[%4ds] %s\n' $(( $(date +%s) - t0 )) "$*" >&2; }

# rule_features DATASET [iraf_vo_run args]: the resolution rule's n_features for the dataset's camera (the value
# iraf_vo_run prints on its first frame).
rule_features() {
  local d="$1" n
  shift
  n=$("$bin/iraf_vo_run" --dataset "$d" "$@" ${vo_args[@]+"${vo_args[@]}"} ${extra[@]+"${extra[@]}"} --frames 1 \
        --out "$out/runs/rule.txt" 2>&1 | sed -n 's/.*resolution rule: .*n_features \([0-9][0-9]*\).*/\1/p' | head -1)
  [[ -n "$n" ]] || die "no resolution-rule line from iraf_vo_run on $d (needed by --draws)"
  echo "$n"
}

# run_modes PRESET CAMERA SEED DATASET GT [iraf_vo_run args]: one row per mode and draw into results.csv.
run_modes() {
  local p="$1" c="$2" s="$3" d="$4" gt="$5" m r k n0=""
  shift 5
  local -a draw_args
  [[ "$draws" == "0" ]] || n0=$(rule_features "$d" "$@") || exit 2
  for k in $draws; do
    draw_args=()
    [[ "$k" == 0 ]] || draw_args=(--set "features.n_features=$(( n0 + k ))")
    for m in $modes; do
      r="$out/runs/${p}_${c}_s$s.$m"
      [[ "$k" == 0 ]] || r="$r.d$k"
      "$bin/iraf_vo_run" --dataset "$d" --mode "$m" --gt "$gt" --out "$r.txt" --stats "$r.json" "$@" \
        ${vo_args[@]+"${vo_args[@]}"} ${extra[@]+"${extra[@]}"} ${draw_args[@]+"${draw_args[@]}"} > "$r.log" 2>&1 \
        || { log "iraf_vo_run failed on $p $c seed $s $m draw $k (see $r.log)"; continue; }
      /usr/bin/python3 - "$r.json" "$r.log" "$p" "$c" "$s" "$m" "$k" >> "$csv" <<'EOF'
import json, re, sys
j = json.load(open(sys.argv[1]))
path = re.search(r"GT path ([0-9.]+) m", open(sys.argv[2]).read())
mm = lambda key: "%.2f" % (1000 * j[key]) if j.get(key) is not None else "nan"
print(",".join(sys.argv[3:7] + [mm("ate_rmse"), str(j["lost_events"]), str(j["resets"]), str(j["tracked"]),
                                 str(j["frames"]), mm("ate_se3_rmse"), "%.5f" % j.get("ate_scale", float("nan")),
                                 path.group(1) if path else "nan", sys.argv[7]]))
EOF
      log "$p $c seed $s $m draw $k: $(tail -1 "$csv")"
    done
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

if [[ -n "$reference" ]]; then  # the other modes' runs of the same sequences and draws from the reference
  /usr/bin/python3 - "$csv" "$reference/results.csv" > "$out/reference.csv" <<'EOF'
import csv, sys
reader = csv.DictReader(open(sys.argv[1]))
rows, fields = list(reader), reader.fieldnames
ref = list(csv.DictReader(open(sys.argv[2])))
key = lambda r: (r["preset"], r["camera"], r["seed"], r.get("draw", "0"))
keys = {key(r) for r in rows}
w = csv.writer(sys.stdout, lineterminator="\n")
w.writerow(fields)
for r in ref:
    if key(r) in keys:
        w.writerow([r.get(k, "0" if k == "draw" else "nan") for k in fields])
EOF
  awk -F, -v modes=" $modes " 'NR > 1 && index(modes, " " $4 " ") == 0' "$out/reference.csv" >> "$csv"
  log "$(( $(wc -l < "$out/reference.csv") - 1 )) runs of $reference on these sequences; the modes not run here from them"
fi

# make_table CSV: the markdown table of a results.csv on stdout.
make_table() {
/usr/bin/python3 - "$1" "$stereo" <<'EOF'
import csv, collections, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
stereo = sys.argv[2] == "1"
key = "se3_mm" if stereo else "ate_mm"  # stereo: the metric (SE(3)-aligned) ATE
# Every run of one sequence and mode (one per --draws offset) -> the geometric mean ATE, the lost events summed,
# the mean Sim(3) scale.
runs = collections.OrderedDict()
draws = set()
for r in rows:
    runs.setdefault((r["preset"], r["camera"], r["seed"]), collections.OrderedDict()).setdefault(r["mode"], []).append(r)
    draws.add(r.get("draw", "0"))
def combine(rs):
    ates = [float(r[key]) for r in rs]
    ate = math.nan if any(math.isnan(a) or a <= 0 for a in ates) else math.exp(sum(map(math.log, ates)) / len(ates))
    return {"ate": ate, "lost": sum(int(r["lost_events"]) for r in rs),
            "scale": sum(float(r["scale"]) for r in rs) / len(rs), "path_m": float(rs[0]["path_m"])}
modes = []
for r in rows:
    if r["mode"] not in modes:
        modes.append(r["mode"])
if len(draws) > 1:
    print("Geometric mean ATE over %d draws of features.n_features (the resolution rule's value + %s), lost events "
          "summed over the draws." % (len(draws), " / ".join(sorted(draws, key=int))))
    print()
def rule(p, by):
    """The done rule on one sequence's modes -> (holds or None when it cannot be judged, iraf / best other,
    iraf / baseline)."""
    ate = lambda m: by[m]["ate"] if m in by else math.nan
    others = [ate(m) for m in ("baseline", "he", "clahe") if m in by and not math.isnan(ate(m))]
    if "iraf" not in by or not others:
        return None, math.nan, math.nan
    rel = ate("iraf") / min(others)
    rel_base = ate("iraf") / ate("baseline") if "baseline" in by else math.nan
    extra_lost = "baseline" in by and by["iraf"]["lost"] > 0 and by["baseline"]["lost"] == 0
    good = rel <= 1.1 and not extra_lost
    if p in ("night", "flashlight"):
        good = good and rel_base <= 0.5
    return good, rel, rel_base
several = len(draws) > 1  # then also: on how many single draws the rule holds
print("| sequence | " + " | ".join(modes) + " | iraf / best other | iraf / baseline | rule |" +
      (" single draws |" if several else "") + (" iraf % of path / scale | metric |" if stereo else ""))
print("|---|" + "---|" * (len(modes) + 3 + (1 if several else 0) + (2 if stereo else 0)))
ok = total = metric_ok = single_ok = single_total = 0
for (p, c, s), by_runs in runs.items():
    by = {m: combine(rs) for m, rs in by_runs.items()}
    cell = lambda m: ("%.1f (%d)" % (by[m]["ate"], by[m]["lost"])) if m in by else "-"
    line = "| %s, %s, seed %s | " % (p, c, s) + " | ".join(cell(m) for m in modes)
    ate = lambda m: by[m]["ate"] if m in by else math.nan
    good, rel, rel_base = rule(p, by)
    verdict = "-"
    if good is not None:
        verdict = "yes" if good else "**no**"
        ok += good
        total += 1
    if several:
        per_draw = collections.defaultdict(dict)  # draw -> mode -> its run
        for m, rs in by_runs.items():
            for r in rs:
                per_draw[r.get("draw", "0")].setdefault(m, []).append(r)
        singles = [rule(p, {m: combine(rs) for m, rs in per_draw[d].items()})[0] for d in per_draw]
        judged = [g for g in singles if g is not None]
        verdict += " | %d of %d" % (sum(judged), len(judged))
        single_ok += sum(judged)
        single_total += len(judged)
    metric = ""
    if stereo and "iraf" in by:
        pct = 0.1 * ate("iraf") / by["iraf"]["path_m"]
        scale = by["iraf"]["scale"]
        good_metric = pct <= 0.5 and abs(scale - 1.0) <= 0.01
        metric_ok += good_metric
        metric = " %.3f %% / %.4f | %s |" % (pct, scale, "yes" if good_metric else "**no**")
    print(line + " | %.2f | %.2f | %s |" % (rel, rel_base, verdict) + metric)
print()
print("rule holds on %d of %d sequences" % (ok, total))
if several:
    print("on single draws: %d of %d (sequence, draw) pairs" % (single_ok, single_total))
if stereo:
    print("metric (iraf SE(3) ATE <= 0.5 %% of the path, scale within 1 %%) on %d of %d sequences" % (metric_ok, total))
EOF
}

make_table "$csv" > "$out/table.md"
cat "$out/table.md"
[[ -n "$reference" ]] || exit 0
make_table "$out/reference.csv" > "$out/reference_table.md"
echo
echo "Against $reference (its table on these sequences: $out/reference_table.md):"
/usr/bin/python3 - "$out/reference_table.md" "$out/table.md" "$out/reference.csv" "$csv" "$stereo" <<'EOF'
import csv, math, sys
def table(path):
    head, rows = None, {}
    for line in open(path):
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if line.startswith("| sequence"):
            head = cells
        elif head and line.startswith("| ") and ", seed " in line:
            rows[cells[0]] = dict(zip(head, cells))
    return rows
before, after = table(sys.argv[1]), table(sys.argv[2])
key = "se3_mm" if sys.argv[5] == "1" else "ate_mm"
def iraf_geo(path):
    a = [float(r[key]) for r in csv.DictReader(open(path)) if r["mode"] == "iraf"]
    a = [x for x in a if x > 0 and not math.isnan(x)]
    return (math.exp(sum(map(math.log, a)) / len(a)), len(a)) if a else (math.nan, 0)
changed = 0
for seq, b in before.items():
    n = after.get(seq)
    if not n or "iraf" not in b or "iraf" not in n or (b["iraf"] == n["iraf"] and b["rule"] == n["rule"]):
        continue
    changed += 1
    mark = "" if b["rule"] == n["rule"] else ("  (now holds)" if n["rule"] == "yes" else "  (no longer holds)")
    print("  %-34s iraf %s -> %s, iraf / best other %s -> %s%s" % (seq, b["iraf"], n["iraf"], b["iraf / best other"],
                                                                  n["iraf / best other"], mark))
holds = lambda t: sum(r.get("rule") == "yes" for r in t.values())
gb, nb = iraf_geo(sys.argv[3])
ga, na = iraf_geo(sys.argv[4])
print("  %d of %d sequences changed; the rule holds on %d -> %d of %d; iraf's geometric mean ATE over %d -> %d runs: "
      "%.3f -> %.3f mm" % (changed, len(before), holds(before), holds(after), len(after), nb, na, gb, ga))
EOF
