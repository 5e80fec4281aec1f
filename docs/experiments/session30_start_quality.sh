#!/bin/bash
# How good the monocular starts are (docs/vo.md, session 30): every suite sequence but
# medium_lowtexture from first frames 0-7, single thread, the first 60 frames only; for each run
# the start line of the log (model, frames, median parallax, direction sigma) and
# `scripts/relative_motion.py --start` (the start pair's direction and rotation error against the
# truth); then per sequence the mean direction error and the starts more than 20 deg off.
#
#   docs/experiments/session30_start_quality.sh PLLVO OUT [CONFIG]
#   (SUITE=/work/synth_suite; SEQS="..." and STARTS="..." narrow the runs)
set -euo pipefail
BIN=$1; OUT=$2; CFG=${3:-}
SUITE=${SUITE:-/work/synth_suite}
HERE=$(cd "$(dirname "$0")/../.." && pwd)
mkdir -p "$OUT"
export BIN OUT CFG SUITE HERE
SEQS=${SEQS:-easy_normal medium_normal difficult_normal easy_lowlight medium_lowlight difficult_lowlight \
easy_flicker medium_flicker difficult_flicker medium_lightoff medium_sudden}
for s in $SEQS; do
  for k in ${STARTS:-0 1 2 3 4 5 6 7}; do echo "$s $k"; done
done | xargs -P 2 -L 1 bash -c '
s=$0; k=$1; d=$OUT/${s}_$k
cfgarg=(); [ -n "$CFG" ] && cfgarg=(--config "$CFG")
"$BIN" run "$SUITE/$s" --mono --single-thread --first "$k" --max-frames 60 "${cfgarg[@]}" --out "$d" > "$d.log" 2>&1 || true
init=$(grep -o "initialisation (.*" "$d.log" | head -1)
rel=$(/usr/bin/python3 "$HERE/scripts/relative_motion.py" "$d" "$SUITE/$s" --start 2>/dev/null | head -1)
echo "$s $k | $init | $rel"
' | sort -k1,1 -k2,2n > "$OUT/summary.txt"
/usr/bin/python3 - "$OUT/summary.txt" <<'PY'
import collections, re, sys
errors = collections.defaultdict(list)
for line in open(sys.argv[1]):
    m = re.search(r"direction ([\d.]+) deg off", line)
    if m:
        errors[line.split()[0]].append(float(m.group(1)))
every = [e for v in errors.values() for e in v]
for name, v in sorted(errors.items()):
    print(f"{name:20s} mean direction error {sum(v) / len(v):5.1f} deg, {sum(e > 20 for e in v)} of {len(v)} over 20 deg")
print(f"{'all':20s} mean direction error {sum(every) / len(every):5.1f} deg, {sum(e > 20 for e in every)} of {len(every)} over 20 deg")
PY
