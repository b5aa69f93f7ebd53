#!/usr/bin/env bash
# train_model.sh: produces the shipped model bundle of one volume, reproducibly (fixed seeds,
# fixed iteration count, fixed thread count):
#   1. ddg generate: training exemplars (indices 0..N-1) and held-out exemplars (indices from
#      1 000 000, never seen in training), from the shipped volume, default design space
#   2. ddg train:    fixed iterations, seed 1, 2 threads; evaluated on the held-out set
#   3. ddg eval:     the first 100 held-out exemplars again, recorded as the bundle's check
# Usage: scripts/train_model.sh VOLUME [ITERATIONS] [COUNT] [SIZE] [WIDTH] [KIND]
#   KIND: unet (the paper's renderer) or decoder (explicit TF, ray cast) [decoder]
#   e.g. scripts/train_model.sh tooth        -> Data/Models/tooth/
set -euo pipefail
cd "$(dirname "$0")/.."
VOLUME=${1:?volume name, e.g. tooth}
ITERATIONS=${2:-4000}
COUNT=${3:-4000}
SIZE=${4:-64}
WIDTH=${5:-16}
KIND=${6:-decoder}
LR=2e-4
[ "$KIND" = decoder ] && LR=1e-3
DDG=build/bin/ddg
WORK=build/models/$VOLUME
OUT=Data/Models/$VOLUME
mkdir -p "$WORK"
$DDG generate --volume "Data/Volumes/$VOLUME.vti" --count "$COUNT" --size "$SIZE" --seed 1 \
  --out "$WORK/train" --quiet
$DDG generate --volume "Data/Volumes/$VOLUME.vti" --count 1000 --size "$SIZE" --seed 1 \
  --first-index 1000000 --out "$WORK/heldout" --quiet
$DDG train --kind "$KIND" --volume "Data/Volumes/$VOLUME.vti" --data "$WORK/train" \
  --eval-data "$WORK/heldout" --eval-count 1000 --out "$WORK/bundle" --lr "$LR" \
  --max-iterations "$ITERATIONS" --minutes 30 --width "$WIDTH" --seed 1 --threads 2 \
  --checkpoint "$WORK/checkpoint.pt"
rm -rf "$OUT.tmp" && cp -r "$WORK/bundle" "$OUT.tmp" && rm -rf "$OUT" && mv "$OUT.tmp" "$OUT"
echo "train_model: wrote $OUT ($(du -sh "$OUT" | cut -f1))"
