#!/usr/bin/env bash
# The numbers in docs/performance.md: rasterizer throughput and engine frame
# time in C++ (Google Benchmark), then whole frames inside Blender.
#   bash bench/run_benchmarks.sh            (after scripts/build.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
echo "machine: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)"
POINTNPR_SHADER_DIR=$PWD/shaders build/bench/bench_render --benchmark_min_time=2 \
  --benchmark_filter='BM_Rasterize|BM_EngineFrame'
blender -b blend_examples/lion_benchmark.blend --python bench/bench_blender.py -- build 8 2>&1 |
  grep -E '^(scene|first|warm|  sync)'
PYTHONPATH=build /usr/bin/python3 bench/bench_marks.py 5
