#!/usr/bin/env bash
# train_model.sh: produces the shipped model bundle of one volume, reproducibly (fixed seeds,
# fixed iteration count, fixed thread count):
#   1. ddg generate: training exemplars (indices 0..N-1) and held-out exemplars (indices from
#      1 000 000, never seen in training), from the shipped volume, default design space
#   2. ddg train:    fixed iterations, seed 1, 2 threads; evaluated on the held-out set
#   3. ddg outline:  the gallery's outline: latents of 50 000 designs (0..49 999 of seed 1, whose
#                    first COUNT are the training exemplars), outline.bin in the bundle
#   4. ddg query-key: the key a query's nearest designs are found by, fitted on 16 000 exemplars
#                    (indices from 3 000 000, neither trained on nor held out), query_key.json
# Usage: scripts/train_model.sh VOLUME [ITERATIONS] [COUNT] [SIZE] [WIDTH] [KIND] [IMAGE_WEIGHT]
#   KIND: unet (the paper's renderer) or decoder (explicit TF, ray cast) [decoder]
#   IMAGE_WEIGHT: decoder's image loss through the differentiable ray caster [100]; the decoder
#   also gets a cosine learning-rate schedule over ITERATIONS
#   DDG (the ddg program) [build/bin/ddg], WORK (scratch folder) [build/models/VOLUME], MODEL_OUT
#   (the bundle folder written, replaced if present) [Data/Models/VOLUME], OUTLINE (designs in
#   the outline; 0: no outline) [50000] and SPEC (a design-space spec JSON for `ddg generate`,
#   e.g. one with "lighting" for lit exemplars; [the documented defaults]) may be set in the
#   environment.
#   e.g. scripts/train_model.sh tooth        -> Data/Models/tooth/
#   The shipped bundles' own commands (e.g. Tooth's SPEC=Data/DesignSpaces/lit.json ... tooth 30000
#   30000) are in the README's table of shipped bundles.
set -euo pipefail
cd "$(dirname "$0")/.."
VOLUME=${1:?volume name, e.g. tooth}
ITERATIONS=${2:-30000}
COUNT=${3:-10000}
SIZE=${4:-64}
WIDTH=${5:-16}
KIND=${6:-decoder}
IMAGE_WEIGHT=${7:-100}
LR=2e-4
EXTRA=()
if [ "$KIND" = decoder ]; then
  LR=1e-3
  EXTRA=(--image-weight "$IMAGE_WEIGHT" --cosine)
fi
DDG=${DDG:-build/bin/ddg}
WORK=${WORK:-build/models/$VOLUME}
OUT=${MODEL_OUT:-Data/Models/$VOLUME}
OUT=${OUT%/}
if [ -z "$OUT" ] || [ "$OUT" = . ] || [ "$OUT" = .. ]; then
  echo "train_model: MODEL_OUT must name a bundle folder" >&2
  exit 1
fi
OUTLINE=${OUTLINE:-50000}
mkdir -p "$WORK" "$(dirname "$OUT")"
SPEC=${SPEC:-}
SPEC_ARGS=()
if [ -n "$SPEC" ]; then
  [ -f "$SPEC" ] || { echo "train_model: SPEC $SPEC is not a file" >&2; exit 1; }
  SPEC_ARGS=(--spec "$SPEC")
fi
# generation is deterministic: a complete dataset of the same volume, spec, count, size, seed and
# first index is reused (the spec used is kept beside it as generated_with_spec.json)
generate() { # DIR COUNT FIRST
  if [ -f "$1/dataset.json" ] && /usr/bin/python3 -c "
import json, sys
d = json.load(open('$1/dataset.json'))
spec = open('$SPEC').read() if '$SPEC' else ''
try:
    used = open('$1/generated_with_spec.json').read()
except OSError:
    used = None
same = (d['count'], d['size'], d['seed'], d['first_index']) == ($2, $SIZE, 1, $3)
sys.exit(0 if same and used == spec else 1)"; then
    echo "train_model: reusing $1"
  else
    rm -f "$1/generated_with_spec.json"
    $DDG generate --volume "Data/Volumes/$VOLUME.vti" "${SPEC_ARGS[@]}" --count "$2" \
      --size "$SIZE" --seed 1 --first-index "$3" --out "$1" --quiet
    cp "${SPEC:-/dev/null}" "$1/generated_with_spec.json"
  fi
}
generate "$WORK/train" "$COUNT" 0
generate "$WORK/heldout" 1000 1000000
$DDG train --kind "$KIND" --volume "Data/Volumes/$VOLUME.vti" --data "$WORK/train" \
  --eval-data "$WORK/heldout" --eval-count 1000 --out "$WORK/bundle" --lr "$LR" \
  --max-iterations "$ITERATIONS" --minutes 45 --width "$WIDTH" --seed 1 --threads 2 \
  --checkpoint "$WORK/checkpoint.pt" "${EXTRA[@]}"
if [ "$OUTLINE" != 0 ]; then
  $DDG outline --model "$WORK/bundle" --volume "Data/Volumes/$VOLUME.vti" --count "$OUTLINE" \
    --seed 1 --threads 2 --quiet
  generate "$WORK/querykey" 16000 3000000
  $DDG query-key --model "$WORK/bundle" --data "$WORK/querykey" --pairs 16000 --threads 2
fi
rm -rf "$OUT.tmp"
cp -r "$WORK/bundle" "$OUT.tmp"
rm -rf "$OUT"
mv "$OUT.tmp" "$OUT"
echo "train_model: wrote $OUT ($(du -sh "$OUT" | cut -f1))"
