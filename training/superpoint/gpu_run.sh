#!/usr/bin/env bash
# The SuperPoint training run as done on a lent GPU machine (docs/superpoint_training.md): the data pack
# made by training/make_data_pack.py travels with the repository as .devpack/, the smoke test runs first,
# then the gpu-short pipeline; the weights (not the optimiser state) and logs are copied to $RESULTS.
#   usage: training/superpoint/gpu_run.sh PACK RESULTS [TOTAL_MINUTES] [extra pipeline options...]
# TOTAL_MINUTES bounds the whole script (smoke test included); the pipeline gets what is left minus one minute.
set -uo pipefail
script_start=$(date +%s)
pack=$(realpath "$1"); results=$(realpath -m "$2"); total=${3:-9.3}; shift 3 || shift $#
mkdir -p "$results"
cd "$(dirname "$0")/.."
export PYTHONUNBUFFERED=1 PLLVO_SHARED="$pack/shared" PLLVO_PHOTOS="$pack/photos"
PY=${PYTHON:-python3}
nvidia-smi -L 2>/dev/null
$PY -c "import torch, cv2, numpy; print('torch', torch.__version__, 'cv2', cv2.__version__, 'numpy', numpy.__version__, 'cuda', torch.cuda.is_available())"
timeout 240 $PY superpoint/smoke_test.py > "$results/smoke.log" 2>&1
status=$?
tail -3 "$results/smoke.log"
[ $status -eq 0 ] || { echo "smoke test failed ($status)"; exit 1; }
synth=()
for d in "$pack"/synth/*/frames; do synth+=(--synth-dir "$d"); done
run=/tmp/sptrain
start=$(date +%s)
minutes=$(awk -v t="$total" -v s=$(( start - script_start )) 'BEGIN { printf "%.2f", t - s / 60 - 1 }')
echo "pipeline budget: $minutes min"
$PY superpoint/pipeline.py --preset gpu-short --device cuda --threads 8 --out "$run" --max-minutes "$minutes" \
  --set data.euroc_every=1 --set data.ecd_first_frame=0 --set data.ecd_every=1 --set data.synth_frames_per_dir=40 "${synth[@]}" "$@" 2>&1 | tee "$results/train.log" |
  grep -v "\] step=" | grep -v "crops, "
echo "pipeline wall time: $(( $(date +%s) - start )) s"
$PY - "$run" "$results" <<'EOF'
import sys, torch
from pathlib import Path
run, results = Path(sys.argv[1]), Path(sys.argv[2])
for stage in ("shapes", "joint"):
    path = run / stage / "checkpoint.pt"
    if path.exists():
        state = torch.load(path, map_location="cpu", weights_only=False)
        keep = {k: v for k, v in state.items() if k != "optimizer"}
        torch.save(keep, results / f"{stage}_weights.pt")
        print(stage, "step", state["step"], "finished", state["finished"], "elapsed_s", round(state["elapsed_s"]))
    for name in ("log.csv", "validation.csv"):
        if (run / stage / name).exists():
            (results / "logs").mkdir(exist_ok=True)
            (results / "logs" / f"{stage}_{name}").write_text((run / stage / name).read_text())
for f in run.glob("*.safetensors"):
    (results / f.name).write_bytes(f.read_bytes())
EOF
mv "$results"/*.log "$results/logs/" 2>/dev/null
(cd "$results" && tar czf logs.tgz logs && rm -rf logs)
ls -la "$results"
