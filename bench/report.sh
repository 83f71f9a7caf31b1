#!/usr/bin/env bash
# Prints the performance ratios that the benchmarks measure today, one run, one thread (thread
# CPU time, so a loaded machine still gives comparable numbers):
#   - G-buffer pass / Embree's rtcIntersect16 4x4 coherent packet rate (bench_render), atrium
#     complexity 3 and 6 (target >= 0.5); and / single-ray rtcIntersect1;
#   - the shared reference (render_reference: the quickstart's 16-spp frame, the 1.06M-triangle
#     atrium at 16 spp, the quickstart at 4 spp) in ns per sample next to Embree's bare
#     rtcIntersect16 in ns per ray over the same sub-sample rays and packets; and next to the
#     bare traversal of all the sample's rays (primary + its shadow rays as rtcOccluded16
#     packets on a filter-free copy of the scene), the issue's measure (target <= 3);
#   - KFR forward (lp_gather) and inverse (lp_reconstruct) map time / cv::warpPolar's time
#     (bench_methods; needs OpenCV, `make deps-bench`);
#   - FovVideoVDP per method-frame (reference side prepared) and its reference side / the FLIP
#     mean of the same frame pair (bench_metrics, quickstart size), and at the headset's own
#     1440x1600 in ms per megapixel and / FLIP on that frame;
#   - `fovsim run configs/quickstart.json` at 1 and 2 threads: its render.scale and frames (the
#     shipped fidelity, docs/fidelity.md) and the 44 s wall target, wall and CPU (user + sys) time,
#     the 2-thread speed-up (wall), the serial fraction estimated from the 2-thread run's
#     per-phase CPU times (manifest.json "phases", sim/experiment/phase_times.h) and the
#     Amdahl speed-up it allows at 2 threads;
#   - `fovsim sweep configs/sweeps/bench_100_cells.json` (100 RMFR cells, 60 frames) at 1 and 2
#     threads: wall time and the 2-thread speed-up;
#   - the reference cache (configs/README.md "cache"): the quickstart at 2 threads into an empty
#     cache, then again with one method parameter changed (methods[kfr].sigma=2.2): wall and CPU
#     time of the second run over the first (target <= 0.5);
#   - the native-resolution perception study (three sweeps, 33 configurations x 40 frames at the
#     displays' own resolutions): wall and CPU time and peak memory (FOVSIM_BENCH_NATIVE=0 skips).
# Every run but the reference-cache pair uses --no-cache, so they time the rendering, not the
# cache. Usage: bench/report.sh BUILD_DIR [MIN_TIME_S]   (make bench-report). Peak RSS is
# reported for the native perception study only.
set -euo pipefail
B=${1:-build}
T=${2:-2}
cd "$(dirname "$0")/.."
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "CPU: $(lscpu | sed -n 's/^Model name: *//p') ($(nproc) CPUs); load: $(cut -d' ' -f1-3 /proc/loadavg)"
"$B/bench_render" --benchmark_filter='BM_PrimaryVsBare/./1|BM_ReferenceVsPacket' --benchmark_min_time="$T" \
  --benchmark_format=json > "$tmp/render.json"
if "$B/bench_methods" --benchmark_list_tests | grep -q opencv; then
  "$B/bench_methods" --benchmark_filter='map/(fovsim_forward|fovsim_inverse|opencv_.*)/tbb:1$' \
    --benchmark_min_time="$T" --benchmark_format=json > "$tmp/methods.json"
else
  echo '{"benchmarks": []}' > "$tmp/methods.json"
  echo "bench_methods has no OpenCV cases (make deps-bench, then reconfigure): KFR ratios skipped"
fi
"$B/bench_metrics" --benchmark_filter='BM_Metrics/flip|BM_Fvvdp' --benchmark_min_time="$T" \
  --benchmark_format=json > "$tmp/metrics.json"
python3 - "$tmp/metrics.json" <<'PY'
import json, sys
bs = json.load(open(sys.argv[1]))["benchmarks"]
m = {b["name"]: b["cpu_time"] for b in bs}
px = {b["name"]: b.get("pixels", 0) for b in bs}
f = m.get("BM_Metrics/flip/1")
for k, label in (("BM_FvvdpMethodFrame/video/1", "one method-frame, video, foveated"),
                 ("BM_FvvdpMethodFrame/image/1", "one method-frame, still image, foveated"),
                 ("BM_FvvdpReference/quarter/1", "reference side of a frame (once for all methods)")):
    if f and k in m:
        print(f"FovVideoVDP {label} / FLIP: {m[k]:.1f} / {f:.1f} ms = {m[k]/f:.2f}"
              + (" (target <= 2.0)" if "MethodFrame" in k else ""))
# At the headset's own 1440x1600 per eye (the native perceptual studies): per megapixel and
# against FLIP on the same frame. The reference PyTorch FovVideoVDP takes 1.2-4.2 s per such
# image on one thread (the reference implementation of Mantiuk et al. 2021).
fn = m.get("BM_Metrics/flip_native/1")
for k, label in (("BM_FvvdpMethodFrame/video_native/1", "one method-frame, video, foveated"),
                 ("BM_FvvdpReference/native/1", "reference side of a frame")):
    if k in m and px.get(k):
        mpx = px[k] / 1e6
        print(f"FovVideoVDP at 1440x1600 ({mpx:.2f} Mpx), {label}: {m[k]:.0f} ms = "
              f"{m[k] / mpx:.0f} ms/Mpx" + (f"; / FLIP ({fn:.0f} ms) = {m[k] / fn:.2f}" if fn else ""))
PY
python3 - "$tmp/render.json" "$tmp/methods.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))["benchmarks"]
seen_ref = False
for b in r:
    if b["name"].startswith("BM_ReferenceVsPacket"):
        seen_ref = True
        if not all(k in b for k in ("ref_ns_per_sample", "packet_ns_per_ray", "ratio_ref_packet",
                                    "shadow_rays_per_sample", "bare_shadow_ns_per_sample",
                                    "ratio_ref_bare", "triangles")):
            print("BM_ReferenceVsPacket: this build reports other counters: " + ", ".join(sorted(b)))
            continue
        _, c, spp = b["name"].split("/")[:3]
        what = (f"atrium complexity {c}, {b['triangles']/1e3:.0f}k tris, {spp} spp"
                + (", the quickstart frame" if (c, spp) == ("1", "16") else ""))
        print(f"reference per sample / Embree bare packet per primary ray ({what}): "
              f"{b['ref_ns_per_sample']:.1f} / {b['packet_ns_per_ray']:.1f} ns = "
              f"{b['ratio_ref_packet']:.2f}")
        print(f"reference per sample / bare packet traversal of all its rays ({what}; primary + "
              f"{b['shadow_rays_per_sample']:.2f} shadow rays): {b['ref_ns_per_sample']:.1f} / "
              f"({b['packet_ns_per_ray']:.1f} + {b['bare_shadow_ns_per_sample']:.1f}) ns = "
              f"{b['ratio_ref_bare']:.2f} (target <= 3)")
        continue
    c = b["name"].split("/")[1]
    print(f"G-buffer / Embree packet (atrium complexity {c}, {b['triangles']/1e3:.0f}k tris): "
          f"{b['gbuf_Mrays_s']:.1f} / {b['packet_Mrays_s']:.1f} Mrays/s = {b['ratio_packet']:.2f} "
          f"(target >= 0.5); vs rtcIntersect1 {b['single_Mrays_s']:.1f} Mrays/s = {b['ratio_single']:.2f}")
if not seen_ref:
    print("reference per sample / Embree bare packet per ray: BM_ReferenceVsPacket is not in this "
          "build's bench_render")
m = {b["name"].split("/")[1]: b["cpu_time"] for b in json.load(open(sys.argv[2]))["benchmarks"]}
for p in ("forward", "inverse"):
    f, o = m.get("fovsim_" + p), m.get("opencv_" + p)
    if f and o:
        print(f"KFR {p} map / cv::warpPolar: {f:.1f} / {o:.1f} ms = {f/o:.2f} (target <= 1.0)")
PY

# timed OUT_JSON FOVSIM_ARGS...: runs $B/fovsim with the arguments (stdout discarded) and writes
# {"wall_s", "cpu_s", "peak_kb"} (wall clock, user + sys CPU and peak resident set of the child)
# to OUT_JSON.
timed() {
  local out=$1
  shift
  python3 - "$B/fovsim" "$@" > "$out" <<'PY'
import json, resource, subprocess, sys, time
t0 = time.monotonic()
subprocess.run(sys.argv[1:], check=True, stdout=subprocess.DEVNULL)
wall = time.monotonic() - t0
ru = resource.getrusage(resource.RUSAGE_CHILDREN)
print(json.dumps({"wall_s": wall, "cpu_s": ru.ru_utime + ru.ru_stime, "peak_kb": ru.ru_maxrss}))
PY
}

# fovsim run configs/quickstart.json at 1 and 2 threads (no plots, images as configured).
for j in 1 2; do
  timed "$tmp/time$j.json" run configs/quickstart.json -o "$tmp/qs$j" -j "$j" --no-plots --no-cache
done
python3 - "$tmp" "$B" <<'PY'
import json, sys
d, B = sys.argv[1], sys.argv[2]
t = {j: json.load(open(f"{d}/time{j}.json")) for j in (1, 2)}
man = json.load(open(f"{d}/qs2/manifest.json"))
ph = man.get("phases", {})
fid, fr = man.get("fidelity", {}), man.get("frames", {})
sim = man.get("simulated_resolution", ["?", "?"])
print(f"quickstart as shipped: render.scale {fid.get('render_scale', '?')} ({sim[0]}x{sim[1]} simulated "
      f"pixels), {fr.get('count', '?')} frames, stride {fr.get('stride', '?')}; target: 2-thread "
      f"wall on 2 idle cores <= 44 s (the 90-frame quickstart at render.scale 0.25 took that)")
for j in (1, 2):
    print(f"quickstart, {j} thread{'s' if j > 1 else ''}: wall {t[j]['wall_s']:.1f} s, "
          f"CPU {t[j]['cpu_s']:.1f} s (user + sys)   [{B}/fovsim run configs/quickstart.json -j {j}]")
print(f"quickstart 2-thread speed-up (wall 1 / wall 2): {t[1]['wall_s'] / t[2]['wall_s']:.2f} "
      f"(target >= 1.8; wall times are only meaningful on an idle machine)")
f = ph.get("serial_fraction")
if f is not None:
    print(f"quickstart serial fraction (2-thread run, per-phase CPU): {f:.3f} (target <= 0.05); "
          f"Amdahl speed-up at 2 threads 1 / (f + (1 - f) / 2) = {1 / (f + (1 - f) / 2):.2f}")
    for k, v in sorted(ph["phases"].items(), key=lambda kv: -kv[1]["cpu_ms"]):
        print(f"  phase {k:10s} wall {v['wall_ms'] / 1e3:7.2f} s  CPU {v['cpu_ms'] / 1e3:7.2f} s  "
              f"serial CPU {v.get('serial_cpu_ms', 0) / 1e3:6.2f} s")
PY

# fovsim sweep configs/sweeps/bench_100_cells.json at 1 and 2 threads.
for j in 1 2; do
  timed "$tmp/swtime$j.json" sweep configs/sweeps/bench_100_cells.json -o "$tmp/sw$j" -j "$j" \
    --no-plots -q --no-cache
done
python3 - "$tmp" "$B" <<'PY'
import json, sys
d, B = sys.argv[1], sys.argv[2]
t = {j: json.load(open(f"{d}/swtime{j}.json")) for j in (1, 2)}
for j in (1, 2):
    print(f"sweep (100 RMFR cells), {j} thread{'s' if j > 1 else ''}: wall {t[j]['wall_s']:.1f} s, "
          f"CPU {t[j]['cpu_s']:.1f} s   [{B}/fovsim sweep configs/sweeps/bench_100_cells.json -j {j}]")
print(f"sweep 2-thread speed-up (wall 1 / wall 2): {t[1]['wall_s'] / t[2]['wall_s']:.2f} "
      f"(target >= 1.8; idle machine only)")
PY

# The reference cache: first run into an empty cache folder, second run with a method parameter
# changed (its references all come from the cache and every other method entry from the method
# memo; results identical to a run without it but for ref_ms and sim_ms).
FOVSIM_CACHE_DIR="$tmp/cache" timed "$tmp/cache1.json" run configs/quickstart.json -o "$tmp/qc1" \
  -j 2 --no-plots
FOVSIM_CACHE_DIR="$tmp/cache" timed "$tmp/cache2.json" run configs/quickstart.json -o "$tmp/qc2" \
  -j 2 --no-plots 'methods[kfr].sigma=2.2'
python3 - "$tmp" "$B" <<'PY'
import json, sys
d, B = sys.argv[1], sys.argv[2]
t = {j: json.load(open(f"{d}/cache{j}.json")) for j in (1, 2)}
man = {j: json.load(open(f"{d}/qc{j}/manifest.json")) for j in (1, 2)}
rc = {j: man[j].get("reference_cache", {}) for j in (1, 2)}
memo = len(man[2].get("memoised_methods", []))
n_methods = len(man[2]["resolved_config"]["methods"])
print(f"reference cache, quickstart -j 2: first run (empty cache) wall {t[1]['wall_s']:.1f} s, "
      f"CPU {t[1]['cpu_s']:.1f} s; second run (methods[kfr].sigma=2.2, "
      f"{rc[2].get('frames_from_cache', 0)} of {rc[2].get('frames_from_cache', 0) + rc[2].get('frames_computed', 0)} "
      f"references from the cache, {memo} of {n_methods} method entries memoised) "
      f"wall {t[2]['wall_s']:.1f} s, CPU {t[2]['cpu_s']:.1f} s")
print(f"reference cache second run / first: wall {t[2]['wall_s'] / t[1]['wall_s']:.2f} (target <= 0.5), "
      f"CPU {t[2]['cpu_s'] / t[1]['cpu_s']:.2f}; {rc[1].get('bytes_written', 0) / 1e6:.0f} MB written   "
      f"[FOVSIM_CACHE_DIR=DIR {B}/fovsim run configs/quickstart.json -j 2, twice]")
PY

# The native-resolution perception study (docs/perception.md): the three grids of KFR sigma (8
# cells, FOVE 2560x1440), TWFR epsilon x phi_F (9, FOVE 1280x1440) and RMFR f_x x f_y (16, Vive Pro
# Eye 1440x1600), 40 frames each at render.scale 1 and render.spp 1, FovVideoVDP against full, at
# 2 threads with the default memory budget. Target: all 33 configurations within 15 minutes of
# wall time on 2 idle cores, within a 16 GB memory budget. Set FOVSIM_BENCH_NATIVE=0 to skip it.
if [ "${FOVSIM_BENCH_NATIVE:-1}" != 0 ]; then
  for s in kfr_sigma twfr_eps_phi rmfr_fx_fy; do
    timed "$tmp/native_$s.json" sweep "configs/perception/$s.json" -o "$tmp/native_$s" -j 2 \
      --no-plots -q --no-cache
  done
  python3 - "$tmp" "$B" <<'PY'
import glob, json, sys
d, B = sys.argv[1], sys.argv[2]
wall = cpu = peak = 0.0
for s in ("kfr_sigma", "twfr_eps_phi", "rmfr_fx_fy"):
    t = json.load(open(f"{d}/native_{s}.json"))
    passes = max((json.load(open(m)).get("memory", {}).get("passes", 1)
                  for m in glob.glob(f"{d}/native_{s}/runs/*/manifest.json")), default=0)
    cells = len(glob.glob(f"{d}/native_{s}/runs/*/manifest.json"))
    print(f"native perception {s}: {cells} cells x 40 frames, wall {t['wall_s'] / 60:.1f} min, "
          f"CPU {t['cpu_s'] / 60:.1f} min, peak {t['peak_kb'] / 1e6:.2f} GB, {passes} pass(es)   "
          f"[{B}/fovsim sweep configs/perception/{s}.json -j 2 --no-cache]")
    wall += t["wall_s"]; cpu += t["cpu_s"]; peak = max(peak, t["peak_kb"])
print(f"native perception study (33 configurations x 40 frames): wall {wall / 60:.1f} min "
      f"(target <= 15 on 2 idle cores), CPU {cpu / 60:.1f} min, peak {peak / 1e6:.2f} GB "
      f"(target <= 16)")
PY
fi
