#!/usr/bin/env bash
# Prints the performance ratios of issue 19 that the benchmarks measure today, one run, one
# thread (thread CPU time, so a loaded machine still gives comparable numbers):
#   - G-buffer pass / Embree's rtcIntersect16 4x4 coherent packet rate (bench_render), atrium
#     complexity 3 and 6; and / single-ray rtcIntersect1;
#   - KFR forward (lp_gather) and inverse (lp_reconstruct) map time / cv::warpPolar's time
#     (bench_methods; needs OpenCV, `make deps-bench`).
# Usage: bench/report.sh BUILD_DIR [MIN_TIME_S]   (make bench-report). Not yet covered: the
# sweep ratio, RSS and the 2-thread speed-up of `fovsim run` (issue 19 items 5 and 7).
set -euo pipefail
B=${1:-build}
T=${2:-2}
cd "$(dirname "$0")/.."
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "CPU: $(lscpu | sed -n 's/^Model name: *//p') ($(nproc) CPUs); load: $(cut -d' ' -f1-3 /proc/loadavg)"
"$B/bench_render" --benchmark_filter='BM_PrimaryVsBare/./1' --benchmark_min_time="$T" \
  --benchmark_format=json > "$tmp/render.json"
if "$B/bench_methods" --benchmark_list_tests | grep -q opencv; then
  "$B/bench_methods" --benchmark_filter='map/(fovsim_forward|fovsim_inverse|opencv_.*)/tbb:1$' \
    --benchmark_min_time="$T" --benchmark_format=json > "$tmp/methods.json"
else
  echo '{"benchmarks": []}' > "$tmp/methods.json"
  echo "bench_methods has no OpenCV cases (make deps-bench, then reconfigure): KFR ratios skipped"
fi
python3 - "$tmp/render.json" "$tmp/methods.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))["benchmarks"]
for b in r:
    c = b["name"].split("/")[1]
    print(f"G-buffer / Embree packet (atrium complexity {c}, {b['triangles']/1e3:.0f}k tris): "
          f"{b['gbuf_Mrays_s']:.1f} / {b['packet_Mrays_s']:.1f} Mrays/s = {b['ratio_packet']:.2f} "
          f"(target >= 0.8); vs rtcIntersect1 {b['single_Mrays_s']:.1f} Mrays/s = {b['ratio_single']:.2f}")
m = {b["name"].split("/")[1]: b["cpu_time"] for b in json.load(open(sys.argv[2]))["benchmarks"]}
for p in ("forward", "inverse"):
    f, o = m.get("fovsim_" + p), m.get("opencv_" + p)
    if f and o:
        print(f"KFR {p} map / cv::warpPolar: {f:.1f} / {o:.1f} ms = {f/o:.2f} (target <= 1.0)")
PY
