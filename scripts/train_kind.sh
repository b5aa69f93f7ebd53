#!/usr/bin/env bash
# Makes the shipped kind network Data/Models/kind (Core's KindNetwork; `ddg kind`) with the
# project's own commands: 1 000 exemplars of each of the eight shipped volumes
# (`ddg generate --spec Data/DesignSpaces/kind.json --seed 11 --screen`), then `ddg train-kind`
# (40 epochs, seed 5, 2 threads; about 25 minutes on 2 cores), then the threshold calibrated on pictures of
# known kind (`ddg kind --calibrate LIST`, a JSON list of [picture, volume] pairs; the project's
# list is the realistic-picture suite of issue 20, outside the repository, so it is optional).
# Usage: scripts/train_kind.sh [WORKDIR [CALIBRATION_LIST]]  (WORKDIR keeps the datasets; default
# build/kind-data; an existing complete dataset is not generated again)
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
DDG=${DDG:-$ROOT/build/bin/ddg}
WORK=${1:-$ROOT/build/kind-data}
LIST=${2:-}
OUT=$ROOT/Data/Models/kind
mkdir -p "$WORK"
args=()
for v in tooth engine chest headsq mri bonsai neghip ironprot; do
  if [ ! -f "$WORK/train_$v/dataset.json" ]; then
    "$DDG" generate --volume "$ROOT/Data/Volumes/$v.vti" --spec "$ROOT/Data/DesignSpaces/kind.json" \
      --count 1000 --out "$WORK/train_$v" --seed 11 --screen --no-viewport --quiet
  fi
  args+=(--dataset "$v=$WORK/train_$v")
done
"$DDG" train-kind "${args[@]}" --out "$OUT" --epochs 40 --seed 5 --threads 2
if [ -n "$LIST" ]; then
  "$DDG" kind --model "$OUT" --calibrate "$LIST"
fi
