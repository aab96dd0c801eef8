#!/usr/bin/env bash
# The numbers in docs/performance.md: rasterizer throughput and engine frame
# time in C++ (Google Benchmark), then whole frames inside Blender.
#   bash bench/run_benchmarks.sh            (after scripts/build.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
echo "machine: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)"
POINTNPR_SHADER_DIR=$PWD/shaders build/bench/bench_render --benchmark_min_time=2 \
  --benchmark_filter='BM_Rasterize|BM_EngineFrame'
# The points mark's rasterizers at 10M points against the scatter reference
# (docs/performance.md, "The native rasterizer"): interleaved, best of 3.
build/bench/bench_rasterizer --benchmark_min_time=1 --benchmark_repetitions=3 \
  --benchmark_enable_random_interleaving=true --benchmark_report_aggregates_only=true | grep -E '_min|^Bench'
blender -b blend_examples/lion_benchmark.blend --python bench/bench_blender.py -- build 8 2>&1 |
  grep -E '^(scene|first|warm|  sync)'
PYTHONPATH=build /usr/bin/python3 bench/bench_marks.py 5
