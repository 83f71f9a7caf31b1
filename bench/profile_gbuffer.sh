#!/usr/bin/env bash
# Where the G-buffer pass's time goes, per stage: BM_GBufferChannels/<complexity>/4 (trace_gbuffer
# with kShadingChannels, one thread) under `perf record`, its samples grouped by function into
# stages and scaled to the benchmark's ns_per_ray (thread CPU time). Stages:
#   traversal       Embree (rtcIntersect16)
#   ray generation  the 4x4 blocks' rays (gbuffer_block_rays) and the tile loop around them
#   hit buffer      TileBatch::trace: each packet's hits copied to the band's hit arrays
#   hit loop        TileBatch::shade: object/material lookup, misses, gathering the triangles'
#                   vertices, normals and uvs (gather), the per-sample path (SampleWriter::hit)
#   refine          the double-precision refinement (gbuffer_lanes' refine)
#   surface         position, uv, footprint and normal (gbuffer_lanes), their stores (finish)
#   texture         TileBatch::texture (sort by material), eval_albedo and the procedural
#                   patterns it calls (box_*, sincos_packet, libm)
#   writes          TileBatch::flush / prefetch_row (staged samples to the frame)
# The first DELAY_MS of the run (scene and BVH build) are not recorded; what is left of the set-up
# shows as "other" and is not scaled. Needs perf (linux-perf) and permission to record
# (kernel.perf_event_paranoid <= 2).
# Usage: bench/profile_gbuffer.sh BUILD_DIR [COMPLEXITY=3] [MIN_TIME_S=5] [DELAY_MS=2000]
set -euo pipefail
B=${1:-build}
C=${2:-3}
T=${3:-5}
D=${4:-2000}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
out=$(perf record -q -D "$D" -o "$tmp/perf.data" "$B/bench_render" \
  --benchmark_filter="BM_GBufferChannels/$C/4/" --benchmark_min_time="$T" 2>&1 | grep BM_)
echo "$out"
ns=$(echo "$out" | sed -n 's/.*ns_per_ray=\([0-9.]*\).*/\1/p')
cat > "$tmp/stages.py" <<'PY'
import re, sys
ns = float(sys.argv[1])
def stage(dso, sym):
    if "embree" in dso: return "traversal (Embree)"
    if "block_rays" in sym or ("trace_gbuffer" in sym and "lambda" in sym): return "ray generation"
    if "TileBatch::trace" in sym: return "hit buffer"
    if "refine" in sym: return "refine"
    if "lanes" in sym or "finish" in sym: return "surface (position, uv, footprint, normal)"
    if "TileBatch::shade" in sym or "Packet::stage" in sym or "SampleWriter::hit" in sym:
        return "hit loop (incl. gather)"
    if "libm" in dso or any(s in sym for s in ("eval_albedo", "box_", "sample_image", "material_",
                                               "sincos", "TileBatch::texture")):
        return "texture"
    if any(s in sym for s in ("flush", "prefetch", "memmove", "memcpy")): return "writes"
    return "other"
share = {}
for line in sys.stdin:
    m = re.match(r"\s*([0-9.]+)%\s+(\S+)\s+\[.\]\s+(.*)", line)
    if m:
        k = stage(m.group(2), m.group(3))
        share[k] = share.get(k, 0.0) + float(m.group(1))
tot = sum(v for k, v in share.items() if k != "other")
for k, v in sorted(share.items(), key=lambda kv: -kv[1]):
    if k != "other":
        print(f"{k:45s} {ns * v / tot:6.1f} ns/ray  ({100 * v / tot:4.1f}%)")
print(f"{'other (set-up, not scaled)':45s} {share.get('other', 0.0):5.1f}% of all samples")
PY
perf report -i "$tmp/perf.data" --no-children --sort dso,sym --stdio 2> /dev/null | grep '%' |
  python3 "$tmp/stages.py" "$ns"
