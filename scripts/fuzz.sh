#!/usr/bin/env bash
# Run latheguard's fuzz targets (fuzz/fuzz_targets) with libFuzzer through cargo-fuzz, each for a
# number of executions, seeded from the repository's own programs, machine files and STL parts.
#
#   scripts/fuzz.sh [RUNS] [TARGET...]      # default: 1000000 runs of parse, machine, stl, check, assume, follow
#
# Needs cargo-fuzz (`cargo install cargo-fuzz`). On a stable toolchain it builds with
# RUSTC_BOOTSTRAP=1 and without a sanitizer (`-s none`): a panic, an abort, an out-of-memory
# (over 2 GiB) or an input that takes more than 2 s (`-timeout=2`) stops the run and leaves the
# input under fuzz/artifacts/TARGET/. The corpus grows under fuzz/corpus/TARGET/ (not committed).
set -euo pipefail
cd "$(dirname "$0")/../fuzz"
runs="${1:-1000000}"
shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(parse machine stl check assume follow)
export RUSTC_BOOTSTRAP=1

seed() {
  local dir="corpus/$1"
  mkdir -p "$dir"
  case "$1" in
    parse | check | assume)
      find ../programs ../tests/cases ../tests/fixtures -name '*.nc' -o -name '*.ngc' |
        while read -r f; do cp -n "$f" "$dir/$(basename "$(dirname "$f")")-$(basename "$f")" 2>/dev/null || true; done ;;
    machine)
      find ../machines ../tests/fixtures ../tests/corpus-jobs/machines -name '*.toml' -size -64k |
        while read -r f; do cp -n "$f" "$dir/$(basename "$(dirname "$f")")-$(basename "$f")" 2>/dev/null || true; done ;;
    follow)
      # Sample streams: the documented fixtures, after the target's two flag bytes (with and
      # without a period; the built-in lathe, the twin-turret one, the milling head's).
      find ../tests/fixtures/follow ../tests/fixtures/docs -name '*.jsonl' -o -name '*.csv' |
        while read -r f; do
          for flags in '\x00\x00' '\x01\x00' '\x00\x01' '\x00\x02'; do
            printf "$flags" | cat - "$f" > "$dir/$(basename "$f")-$(printf "$flags" | od -An -tx1 | tr -d ' ')"
          done
        done ;;
    stl)
      # Small parts only: libFuzzer's inputs stay under -max_len.
      find ../machines ../tests/fixtures -name '*.stl' -size -64k |
        while read -r f; do cp -n "$f" "$dir/$(basename "$f")" 2>/dev/null || true; done ;;
  esac
}

for t in "${targets[@]}"; do
  seed "$t"
  echo "== $t: $runs runs"
  cargo fuzz run -O -s none "$t" "corpus/$t" -- \
    -runs="$runs" -timeout=2 -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1
done
