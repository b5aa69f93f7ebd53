#!/usr/bin/env bash
# demo.sh: the main job on the embedded default (Tooth and its shipped model) — sets up, builds,
# then runs the whole story in ParaView (pvpython under Xvfb): the design gallery, a shipped
# ParaView screenshot as the query, its TF and the TF reconstructed from it applied in ParaView,
# renders and presets saved, metrics and step times printed (Python/examples/main_job.py).
# Usage: scripts/demo.sh [OUT_DIR]     (default: build/demo)
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
OUT=${1:-build/demo}
scripts/with-xvfb.sh "${DDG_BUILD_DIR:-build}/bin/pvpython" Python/examples/main_job.py "$OUT"
