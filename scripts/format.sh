#!/usr/bin/env bash
# format.sh: formats C++ (clang-format, .clang-format) and Python (black, 100 columns).
# Usage: scripts/format.sh [--check]
set -euo pipefail
cd "$(dirname "$0")/.."
mode=-i
black_mode=""
if [ "${1:-}" = "--check" ]; then mode="--dry-run --Werror"; black_mode="--check"; fi
git ls-files '*.h' '*.cxx' | xargs clang-format $mode
git ls-files '*.py' | xargs black -q -l 100 $black_mode
