#!/usr/bin/env bash
# Builds the libFuzzer targets of the readers (build-fuzz, clang with
# -fsanitize=fuzzer,address,undefined) and runs each one for a short while,
# seeded with the test files of its format. Fails on any crash, sanitizer
# report, leak, timeout or out-of-memory.
#
#   scripts/fuzz_smoke.sh                 # CI: a fixed, reproducible run per target
#   FUZZ_SECONDS=600 scripts/fuzz_smoke.sh las ply   # a longer, random campaign
#   (the laz target's smoke run does FUZZ_RUNS_LAZ inputs, default 2000, of
#   at most 16 KB)
#
# The smoke run (used by scripts/test.sh) is deterministic: fixed seed, fixed
# number of inputs (FUZZ_RUNS, default 100000), fresh corpus, so CI cannot
# fail by chance on a finding that a later run would not reproduce; new
# findings come from campaigns. Campaign corpora grow in
# build-fuzz/corpus/<format>; crashing inputs are saved in build-fuzz/artifacts/.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
secs=${FUZZ_SECONDS:-}
runs=${FUZZ_RUNS:-100000}
formats=("$@")
((${#formats[@]})) || formats=(las laz e57 ply spz pcd text roundtrip scan_cache)

cmake -S . -B build-fuzz -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DPOINTNPR_FUZZ=ON -DPOINTNPR_BUILD_TESTS=OFF -DPOINTNPR_BUILD_BENCH=OFF >/dev/null
cmake --build build-fuzz -j2 --target "${formats[@]/#/fuzz_}"

# Seeds: the test files of the format plus the small ones in fuzz/seeds/.
seed_files() {
  local names
  case $1 in
    las) names=(-name '*.las') ;;  # LAZ: fuzz_laz (slow to decode; its own settings)
    laz) names=(-name '*.laz') ;;
    e57) names=(-name '*.e57') ;;  # checksums unchecked: fuzz/fuzz_e57.cpp
    ply | roundtrip) names=(-name '*.ply') ;;
    pcd) names=(-name '*.pcd') ;;
    spz) names=(-name '*.spz') ;;
    text) names=(-name '*.xyz' -o -name '*.pts' -o -name '*.txt' -o -name '*.csv' -o -name '*.asc') ;;
    scan_cache) names=(-name '*.pnprcache') ;;
  esac
  local dirs=(tests/data/io)
  [[ -d fuzz/seeds/$1 ]] && dirs+=("fuzz/seeds/$1")
  find "${dirs[@]}" -type f \( "${names[@]}" \)
}

mkdir -p build-fuzz/artifacts
# One target's run; its summary goes to stdout, "FAILED" on a finding.
fuzz_one() {
  local f=$1 seeds=build-fuzz/seeds/$1 corpus=build-fuzz/corpus/$1 limit max_len
  rm -rf "$seeds"
  if [[ -z $secs ]]; then
    rm -rf "$corpus"  # reproducible: the same inputs every time
    limit=(-seed=1 -runs="$runs")
    # LAZ inputs decode thousands of points each (some 20 ms under the
    # sanitizers): fewer, shorter inputs keep the smoke run near a minute.
    [[ $f == laz ]] && limit=(-seed=1 -runs="${FUZZ_RUNS_LAZ:-2000}")
  else
    limit=(-max_total_time="$secs")
  fi
  mkdir -p "$seeds" "$corpus"
  seed_files "$f" | while read -r file; do cp "$file" "$seeds/"; done
  echo "=== fuzz_$f: $(ls "$seeds" | wc -l) seed files, ${limit[*]}"
  # -max_len keeps mutation fast (the largest seeds are ~1 MB; longer inputs
  # are cut, which itself exercises the truncation checks).
  max_len=65536
  [[ $f == laz ]] && max_len=16384
  if ! build-fuzz/fuzz/fuzz_$f "$corpus" "$seeds" "${limit[@]}" -rss_limit_mb=2048 \
      -timeout=10 -max_len="$max_len" -print_final_stats=1 \
      -artifact_prefix="$root/build-fuzz/artifacts/$f-" >"build-fuzz/fuzz_$f.log" 2>&1; then
    echo "=== fuzz_$f: FAILED (log: build-fuzz/fuzz_$f.log)"
    grep -E "ERROR|SUMMARY|Test unit written|runtime error" "build-fuzz/fuzz_$f.log" | head -20
  else
    echo "=== fuzz_$f: ok, $(grep -Eo 'stat::number_of_executed_units: *[0-9]+' "build-fuzz/fuzz_$f.log" | grep -Eo '[0-9]+$') executions"
  fi
}

# Each target is one single-threaded process with its own fixed inputs: as
# many run at once as there are cores, their summaries printed in order.
slots=$(nproc)
for f in "${formats[@]}"; do
  while (($(jobs -rp | wc -l) >= slots)); do wait -n || true; done
  fuzz_one "$f" >"build-fuzz/fuzz_$f.summary" 2>&1 &
done
wait
status=0
for f in "${formats[@]}"; do
  cat "build-fuzz/fuzz_$f.summary"
  grep -q "^=== fuzz_$f: ok" "build-fuzz/fuzz_$f.summary" || status=1
done
exit $status
