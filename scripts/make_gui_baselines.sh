#!/bin/bash
# Regenerates the baselines of the Design Gallery GUI tests (Testing/Data/Baselines/gui_*.png):
# runs the tests without baselines, so ParaView saves what the render view shows, and copies
# those images in. Review them (and the tests' other checks) before committing.
#
#   bash scripts/make_gui_baselines.sh [BUILD_DIR]     (default: build)
set -euo pipefail
cd "$(dirname "$0")/.."
build="${1:-build}"
baselines=Testing/Data/Baselines
keep=$(mktemp -d)
trap 'rm -rf "$keep"' EXIT
mv "$baselines"/gui_*.png "$keep"/ 2>/dev/null || true
ctest --test-dir "$build" -R 'Plugin\.Gui(QueryApply|ThumbnailApply)' > /dev/null || true
for f in "$build"/Testing/Plugin/gui/*/gui_*.png; do
  cp "$f" "$baselines"/
  echo "baseline: $baselines/$(basename "$f")"
done
