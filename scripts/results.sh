#!/usr/bin/env bash
# Reruns the measurements of docs/results.md and writes them, with a summary table, to one folder.
#
#   scripts/results.sh [OUT]            # default OUT: out/results (ignored by git)
#
# Environment:
#   PLLVO        the executable (default build/bin/pllvo; build first with scripts/build.sh)
#   PLLVO_DATA   the real-camera fixtures (default ../shared/data)
#   SUITE        the rendered synthetic suite (default OUT/synth_suite; rendered when missing:
#                easy_normal 30 s, the other eleven presets 10 s, stereo, seed 1)
#   STARTS       start frames of the monocular low-light runs (default "0 1 2 3 4 5 6 7"; empty: skip)
#   SKIP_SUITE=1, SKIP_SPEED=1   leave those parts out
#
# What it runs (each part writes OUT/<part>/<name>/ with the run's stats.json and a .log beside it):
#   real/       pllvo run on every fixture, threaded (the default): EuRoC stereo, TUM, ECD, KITTI 06 mono
#               (kitti_04_mono51), KITTI 06 and 01 stereo and mono, and KITTI 06 / 01 stereo with --realtime
#   suite/      scripts/vo_suite.py over the synthetic suite, stereo and mono, threaded, start frame 0
#   starts/     mono medium_lowlight and difficult_lowlight, --single-thread, one run per start frame
#   speed/      pllvo demo, and bench_vo (pllvo against ORB on easy_normal) when build/bin/bench_vo exists
# and OUT/summary.md: one table per part, with the date, the commit and the machine at the top.
# Times: real ~5 min, rendering ~15-30 min (once), suite ~10 min, starts ~15 min, speed ~3 min on 2 cores.
set -uo pipefail
cd "$(dirname "$0")/.."

OUT=${1:-out/results}
PLLVO=${PLLVO:-build/bin/pllvo}
DATA=${PLLVO_DATA:-../shared/data}
SUITE=${SUITE:-$OUT/synth_suite}
STARTS=${STARTS-0 1 2 3 4 5 6 7}
PY=/usr/bin/python3
[ -x "$PY" ] || PY=python3

[ -x "$PLLVO" ] || { echo "results.sh: $PLLVO not found (build with scripts/build.sh, or set PLLVO)" >&2; exit 2; }
[ -d "$DATA" ] || { echo "results.sh: fixtures not found at $DATA (set PLLVO_DATA)" >&2; exit 2; }
mkdir -p "$OUT"/{real,suite,starts,speed}

commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)
git diff --quiet HEAD 2>/dev/null || commit="$commit (with uncommitted changes)"
{
  echo "date: $(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "commit: $commit"
  echo "machine: $(grep -m1 'model name' /proc/cpuinfo 2>/dev/null | cut -d: -f2- | sed 's/^ *//'), $(nproc) cores"
  echo "load before: $(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null)"
  echo "pllvo: $("$PLLVO" --version 2>&1)"
} > "$OUT/meta.txt"
cat "$OUT/meta.txt"

# run NAME PART ARGS...: pllvo run ARGS --out OUT/PART/NAME, log beside it; never stops the script.
run() {
  local name=$1 part=$2
  shift 2
  local dir="$OUT/$part/$name"
  rm -rf "$dir"
  echo "== $part/$name: pllvo run $* --out $dir"
  "$PLLVO" run "$@" --out "$dir" > "$dir.log" 2>&1 || echo "   exit $? (see $dir.log)"
}

# ---- real fixtures (threaded default)
run euroc_stereo       real "$DATA/euroc_V1_01_easy_micro"
run tum_mono           real "$DATA/tum_fr3_office_snippet"
run ecd_mono           real "$DATA/ecd_slider_hdr_close_149"
run kitti06_mono51     real "$DATA/kitti_04_mono51"
run kitti06_stereo     real "$DATA/kitti_06_stereo51/sequences/06"
run kitti06_mono       real "$DATA/kitti_06_stereo51/sequences/06" --mono
run kitti01_stereo     real "$DATA/kitti_01_stereo51/sequences/01"
run kitti01_mono       real "$DATA/kitti_01_stereo51/sequences/01" --mono
run kitti06_stereo_rt  real "$DATA/kitti_06_stereo51/sequences/06" --realtime
run kitti01_stereo_rt  real "$DATA/kitti_01_stereo51/sequences/01" --realtime

# ---- synthetic suite
PRESETS="easy_normal easy_lowlight easy_flicker medium_normal medium_lowlight medium_flicker medium_lightoff
         medium_sudden medium_lowtexture difficult_normal difficult_lowlight difficult_flicker"
render() {
  local p=$1
  [ -d "$SUITE/$p/mav0" ] && return 0
  local duration=()
  [ "$p" = easy_normal ] || duration=(--duration 10)
  echo "== render $p"
  "$PLLVO" synth --preset "$p" --stereo "${duration[@]}" --out "$SUITE/$p" --overwrite > "$SUITE/$p.render.log" 2>&1 ||
    echo "   render of $p failed (see $SUITE/$p.render.log)"
}
if [ "${SKIP_SUITE:-0}" != 1 ] || [ -n "$STARTS" ] || [ "${SKIP_SPEED:-0}" != 1 ]; then
  mkdir -p "$SUITE"
  for p in $PRESETS; do render "$p"; done
fi

if [ "${SKIP_SUITE:-0}" != 1 ]; then
  for mode in stereo mono; do
    echo "== suite, $mode (scripts/vo_suite.py)"
    "$PY" scripts/vo_suite.py "$SUITE" --out "$OUT/suite/$mode" --modes "$mode" --jobs 1 --pllvo "$PLLVO" \
      --json "$OUT/suite/$mode.json" > "$OUT/suite/$mode.md" 2> "$OUT/suite/$mode.err"
    tail -n 1 "$OUT/suite/$mode.md"
  done
fi

# ---- monocular low light over start frames (single thread)
for seq in medium_lowlight difficult_lowlight; do
  for k in $STARTS; do
    run "${seq}_first$k" starts "$SUITE/$seq" --mono --single-thread --first "$k"
  done
done

# ---- speed
if [ "${SKIP_SPEED:-0}" != 1 ]; then
  echo "== pllvo demo"
  "$PLLVO" demo > "$OUT/speed/demo.txt" 2>&1 || echo "   demo exit $?"
  tail -n 5 "$OUT/speed/demo.txt"
  if [ -x build/bin/bench_vo ]; then
    echo "== bench_vo on easy_normal (pllvo and ORB)"
    PLLVO_BENCH_SEQUENCE="$SUITE/easy_normal" build/bin/bench_vo --benchmark_filter='orb|pllvo' \
      --benchmark_counters_tabular=true > "$OUT/speed/bench_vo.txt" 2>&1 || echo "   bench_vo exit $?"
  else
    echo "== bench_vo not built (cmake --build build --target bench_vo): skipped" | tee "$OUT/speed/bench_vo.txt"
  fi
fi

# ---- summary
"$PY" - "$OUT" <<'EOF'
import json, os, sys

out = sys.argv[1]
lines = [open(os.path.join(out, "meta.txt")).read().strip(), ""]


def load(d):
    p = os.path.join(d, "stats.json")
    return json.load(open(p)) if os.path.exists(p) else None


def row(name, s):
    if s is None:
        return f"| {name} | run failed | | | | | | |"
    e = s.get("trajectory_error") or {}
    ate = f"{e['ate_rmse_m']:.4f} m = {e['ate_percent_of_path']:.2f} % ({e['align']})" if e else "-"
    lost = ", ".join(f"{l['first_frame']}-{l['last_frame']}" for l in s.get("lost_intervals", [])) or "none"
    rt = s.get("realtime")
    rt = (f"{rt['frames_dropped']} dropped, latency mean {rt['latency_mean_ms']:.0f} / p95 {rt['latency_p95_ms']:.0f}"
          f" / max {rt['latency_max_ms']:.0f} ms") if rt else ""
    return (f"| {name} | {s['mode']} | {s['tracked_frames']}/{s['frames']} | {s['keyframes']} | {s['resets']} | "
            f"lost {lost} | {ate}; largest distance from the start {s['estimate']['max_displacement']:.4f} | "
            f"{s['frames_per_second']:.1f} {rt} |")


header = ["| run | mode | tracked | keyframes | resets | lost frames | ATE | frames/s |", "|---|---|---|---|---|---|---|---|"]
for part in ("real", "starts"):
    base = os.path.join(out, part)
    names = sorted(d for d in os.listdir(base) if os.path.isdir(os.path.join(base, d))) if os.path.isdir(base) else []
    if not names:
        continue
    lines += [f"## {part}", ""] + header + [row(n, load(os.path.join(base, n))) for n in names] + [""]
    if part == "starts":
        for seq in ("medium_lowlight", "difficult_lowlight"):
            vals = []
            for n in names:
                s = load(os.path.join(base, n))
                if n.startswith(seq + "_first") and s and s.get("trajectory_error"):
                    vals.append(s["trajectory_error"]["ate_percent_of_path"])
            if vals:
                lines.append(f"{seq} mono, single thread: {' '.join(f'{v:.2f}' for v in vals)}, mean {sum(vals) / len(vals):.2f} %")
        lines.append("")
for mode in ("stereo", "mono"):
    p = os.path.join(out, "suite", mode + ".md")
    if os.path.exists(p):
        lines += [f"## suite, {mode}", "", open(p).read().strip(), ""]
for f in ("demo.txt", "bench_vo.txt"):
    p = os.path.join(out, "speed", f)
    if os.path.exists(p):
        lines += [f"## speed: {f}", "", "```", open(p).read().strip()[-4000:], "```", ""]
open(os.path.join(out, "summary.md"), "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
EOF
echo "summary: $OUT/summary.md"
