#!/usr/bin/env bash
# How long a fresh clone takes to build: `cargo install --locked --path .` (the first `check`) and,
# with --tests, `cargo test --no-run` (the first test result), each from an empty target folder.
# Prints wall-clock seconds and the binary's size. Run it on an idle machine: it measures time.
#   scripts/fresh-build.sh [--tests] [-j N]
set -euo pipefail
cd "$(dirname "$0")/.."
tests=false
jobs=()
while [ $# -gt 0 ]; do
  case "$1" in
    --tests) tests=true ;;
    -j) jobs=(-j "$2"); shift ;;
    *) echo "usage: $0 [--tests] [-j N]" >&2; exit 2 ;;
  esac
  shift
done
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
git clone --quiet . "$work/clone"
cd "$work/clone"
start=$(date +%s)
CARGO_TARGET_DIR="$work/target" cargo install --quiet --locked --path . --root "$work/root" ${jobs[@]+"${jobs[@]}"}
end=$(date +%s)
echo "cargo install --locked --path . : $((end - start)) s, binary $(du -h "$work/root/bin/latheguard" | cut -f1)"
if $tests; then
  start=$(date +%s)
  CARGO_TARGET_DIR="$work/target-test" cargo test --quiet --no-run ${jobs[@]+"${jobs[@]}"} 2>/dev/null
  end=$(date +%s)
  echo "cargo test --no-run           : $((end - start)) s"
fi
