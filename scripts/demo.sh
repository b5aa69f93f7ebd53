#!/usr/bin/env bash
# demo.sh: the main job on the embedded default data — sets up, builds, then renders the Tooth
# with a shipped ParaView preset and view, and prints where the image is.
# Usage: scripts/demo.sh [output.png]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
OUT=${1:-build/demo/tooth.png}
mkdir -p "$(dirname "$OUT")"
build/bin/ddg render \
  --volume Data/Volumes/tooth.vti \
  --tf Data/TransferFunctions/tooth_dentin_enamel.json \
  --view Data/Views/tooth_oblique.json \
  --out "$OUT"
echo "demo: the Tooth rendered with the preset 'Tooth dentin and enamel' is at $(realpath "$OUT")"
