#!/usr/bin/env bash
# Runs `pllvo run` with each point front end over the given sequences and prints one table row
# per (sequence, front end): tracked frames, keyframes, resets, ATE RMSE (m and % of the path)
# and frames/s. Used for the front-end comparison in docs/vo.md.
#   scripts/vo_frontend_compare.sh [--single-thread] SEQ_DIR...
# SuperPoint weights: the nn lookup ($PLLVO_MODELS, models/); e.g.
#   PLLVO_MODELS=../shared/models scripts/vo_frontend_compare.sh --single-thread /tmp/synth/easy_normal
set -euo pipefail
cd "$(dirname "$0")/.."
extra=()
if [[ "${1:-}" == --* ]]; then extra+=("$1"); shift; fi
out=${PLLVO_COMPARE_OUT:-/tmp/pllvo_frontend_compare}
frontends=${PLLVO_FRONTENDS:-"orb superpoint"}
mkdir -p "$out"
printf "| sequence | front end | tracked | keyframes | resets | ATE RMSE m | ATE %% of path | frames/s |\n|---|---|---|---|---|---|---|---|\n"
for seq in "$@"; do
  for fe in $frontends; do
    dir="$out/$(basename "$seq")_$fe"
    rm -rf "$dir"
    build/bin/pllvo run "$seq" --out "$dir" --frontend "$fe" "${extra[@]}" >/dev/null 2>"$dir.log" || { echo "| $(basename "$seq") | $fe | failed: see $dir.log |"; continue; }
    /usr/bin/python3 - "$dir/stats.json" "$(basename "$seq")" "$fe" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
e = s.get("trajectory_error")
ate = f"{e['ate_rmse_m']:.4f} | {e['ate_percent_of_path']:.2f}" if e else "- | -"
print(f"| {sys.argv[2]} | {sys.argv[3]} | {s['tracked_frames']}/{s['frames']} | {s['keyframes']} | {s['resets']} | {ate} | {s['frames_per_second']:.1f} |")
PY
  done
done
