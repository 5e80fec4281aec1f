#!/usr/bin/env bash
# Installs the build to a temporary prefix, builds examples/cpp_minimal against the install and runs
# it on a real fixture; runs the installed `pllvo` and imports the installed Python module.
#   usage: scripts/test_install.sh [BUILD_DIR]   (default: build)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
shared=${PLLVO_SHARED:-../shared}
fixture=$(realpath "$shared/data/euroc_V1_01_easy_micro")
prefix=$(mktemp -d /tmp/pllvo_install.XXXXXX)
trap '[ -n "${PLLVO_KEEP_INSTALL:-}" ] || rm -rf "$prefix"' EXIT

cmake --install "$build" --prefix "$prefix/usr" >/dev/null
cmake -S examples/cpp_minimal -B "$prefix/example" -DCMAKE_PREFIX_PATH="$prefix/usr" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$prefix/example" -j "${PLLVO_JOBS:-2}" >/dev/null

# Run from elsewhere with no repository around: the models must come from the install.
(cd "$prefix" && env -u PLLVO_MODELS "$prefix/example/cpp_minimal" "$fixture" "$prefix/out" \
   > "$prefix/poses.txt" 2> "$prefix/example.log")
# pllvo's log goes to stdout with the poses; the log lines start with a [date].
grep -q "weights $prefix/usr/share/pllvo/models/" "$prefix/poses.txt" "$prefix/example.log" || {
  echo "test_install: the example did not load the installed weights:"; grep -h "weights" "$prefix/poses.txt" "$prefix/example.log"; exit 1; }
frames=$(grep -vc '^\[' "$prefix/poses.txt" || true)
tracked=$(grep -c " tracking " "$prefix/poses.txt" || true)
grep -q '"frontend": "superpoint"' "$prefix/out/stats.json" || { echo "test_install: the example did not run SuperPoint (models not found in the install?)"; exit 1; }
for f in trajectory.tum keyframes.tum map.ply stats.json; do
  [ -s "$prefix/out/$f" ] || { echo "test_install: $f missing from the example's output"; exit 1; }
done
if [ "$frames" -lt 70 ] || [ "$tracked" -lt $((frames - 5)) ]; then
  echo "test_install: cpp_minimal printed $frames poses, $tracked tracked (expected at least 70, nearly all tracked)"
  exit 1
fi
(cd "$prefix" && env -u PLLVO_MODELS "$prefix/usr/bin/pllvo" run "$fixture" --max-frames 3 --out "$prefix/run" \
   > "$prefix/run.log" 2>&1)
grep -q "weights $prefix/usr/share/pllvo/models/" "$prefix/run.log" || {
  echo "test_install: the installed pllvo did not load the installed weights:"; grep "weights" "$prefix/run.log"; exit 1; }
PYTHONPATH="$prefix/usr/lib/pllvo/python" /usr/bin/python3 -c "import pllvo, sys; assert pllvo._installed_models_dir(), 'installed models not found'; print('python', pllvo.__file__)" >/dev/null
echo "test_install: installed to a temporary prefix; cpp_minimal tracked $tracked of $frames frames of $(basename "$fixture") with the installed weights; the installed pllvo finds them too; the installed Python module loads"
