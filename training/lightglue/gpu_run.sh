#!/usr/bin/env bash
# The LightGlue training run as done on a lent GPU machine (docs/lightglue_training.md): the data pack made by
# training/make_data_pack.py (--held-out, --synth-eval) travels as .devpack/; smoke run, then the gpu-short
# training for what the time budget leaves, export (fp16), and the held-out evaluation against MNN.
#   usage: training/lightglue/gpu_run.sh PACK SUPERPOINT RESULTS [TOTAL_MINUTES [INIT_WEIGHTS [train options...]]]
# A second call continues from the first call's exported weights (INIT_WEIGHTS; the optimiser starts afresh).
set -uo pipefail
script_start=$(date +%s)
pack=$(realpath "$1"); superpoint=$(realpath "$2"); results=$(realpath -m "$3"); total=${4:-9.4}
init=(); [ -n "${5:-}" ] && init=(--init "$(realpath "$5")"); shift 5 2>/dev/null || shift $#
mkdir -p "$results/logs"
cd "$(dirname "$0")/.."
export PYTHONUNBUFFERED=1 PLLVO_SHARED="$pack/shared" PLLVO_PHOTOS="$pack/photos"
PY=${PYTHON:-python3}
nvidia-smi -L 2>/dev/null
synth=(); for d in "$pack"/synth/*/; do synth+=(--synth-dir "$d"); done
held=(); for d in "$pack"/synth_eval/*/; do held+=(--synth-dir "$d"); done
timeout 120 $PY lightglue/train.py --preset smoke --device cuda --superpoint "$superpoint" --out /tmp/lgsmoke \
  "${synth[@]:0:2}" > "$results/logs/smoke.log" 2>&1 || { tail -20 "$results/logs/smoke.log"; exit 1; }
echo "smoke run ok: $(tail -1 /tmp/lgsmoke/log.csv)"
elapsed=$(( $(date +%s) - script_start ))
minutes=$(awk -v t="$total" -v s="$elapsed" 'BEGIN { printf "%.2f", t - s / 60 - 2.2 }')
echo "training for $minutes min"
$PY lightglue/train.py --preset gpu-short --device cuda --threads 8 --superpoint "$superpoint" --out /tmp/lg \
  --set minutes="$minutes" "${synth[@]}" "${init[@]}" "$@" 2>&1 | tee "$results/logs/train.log" | grep -v "\] step="
cp /tmp/lg/log.csv /tmp/lg/validation.csv "$results/logs/" 2>/dev/null
$PY lightglue/export.py /tmp/lg/checkpoint.pt "$results/pllvo_lightglue.safetensors"
timeout 150 $PY lightglue/evaluate.py --device cuda --lightglue "$results/pllvo_lightglue.safetensors" \
  --superpoint "$superpoint" "${held[@]}" --synth-pairs 15 --out "$results/logs/lg_eval.json" > "$results/logs/eval.log" 2>&1
tail -60 "$results/logs/eval.log"
(cd "$results" && tar czf logs.tgz logs && rm -rf logs)
echo "total wall time: $(( $(date +%s) - script_start )) s"
ls -la "$results"
