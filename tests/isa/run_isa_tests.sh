#!/usr/bin/env bash
# Runs the tests that exercise CPU-specific code under every code path this machine has:
# each Embree ISA (FOVSIM_EMBREE_ISA, sim/render/embree_device.h) and each SIMD kernel path
# of fovsim's own loops (FOVSIM_SIMD, sim/foveation/simd_kernels.h), and glibc's libm with its
# FMA/AVX2 variants masked (GLIBC_TUNABLES). The selected tests cover
# dynamic scenes (instanced BVH, recommits), TWFR, FLC (RSM, VPL visibility), the mapping
# fast paths and the golden regression of every method; goldens must match on every path.
# Usage: tests/isa/run_isa_tests.sh BUILD_DIR     (ctest runs it as IsaPaths; make test)
# Ends with one line naming the paths exercised and "N passed, N failed".
set -uo pipefail
B=${1:-build}
cd "$(dirname "$0")/../.."
per_test_timeout=120

info=$("$B/fovsim" info --json) || { echo "fovsim info failed"; exit 1; }
list() { echo "$info" | sed -E "s/.*\"$1\":\[([^]]*)\].*/\1/" | tr -d '"' | tr ',' ' '; }
isas=$(list embree_isas)
simds=$(list simd_paths)
[ -n "$isas" ] && [ -n "$simds" ] || { echo "cannot parse: $info"; exit 1; }

passed=0; failed=0; failures=""
run() {  # run LABEL ENV... -- CMD...
  local label=$1; shift
  local envs=()
  while [ "$1" != "--" ]; do envs+=("$1"); shift; done; shift
  # A filter that selects no test would "pass" without testing anything: count first.
  local n
  n=$(env "${envs[@]}" "$@" --gtest_list_tests 2> /dev/null | grep -c '^  ')
  if [ "$n" -eq 0 ]; then
    failed=$((failed + 1)); failures="$failures $label"
    echo "FAILED: $label selects no test ($*)"; return
  fi
  if env "${envs[@]}" timeout "$per_test_timeout" "$@" > /tmp/fovsim_isa_$$.log 2>&1; then
    passed=$((passed + 1))
  else
    failed=$((failed + 1)); failures="$failures $label"
    echo "FAILED: $label (${envs[*]} $*)"; tail -n 30 /tmp/fovsim_isa_$$.log
  fi
}

for isa in $isas; do
  E=(FOVSIM_EMBREE_ISA=$isa)
  run "render[$isa]" "${E[@]}" -- "$B/test_render" --gtest_filter='Render.*Dynamic*:Render.Deterministic*:Render.Motion*:Render.Shadow*:Render*Rsm*:Rsm*:Vpl*:GBufferLanes*'
  run "twfr+flc[$isa]" "${E[@]}" -- "$B/test_foveation" --gtest_filter='Twfr*:Flc*'
  run "golden[$isa]" "${E[@]}" -- "$B/test_app" --gtest_filter='Golden*'
done
for simd in $simds; do
  S=(FOVSIM_SIMD=$simd)
  run "mapping[$simd]" "${S[@]}" -- "$B/test_foveation" --gtest_filter='Mapping*:Kfr*:Rmfr*'
  run "golden[$simd]" "${S[@]}" -- "$B/test_app" --gtest_filter='Golden*'
done
# glibc's libm picks FMA/AVX2 variants of sinf, cosf, powf, exp, log ... at run time (ifunc);
# masking those CPU features makes it use its SSE2 variants, as on a CPU without FMA.
LIBM=(GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA,-FMA4,-AVX,-AVX512F)
run "golden[libm-sse2]" "${LIBM[@]}" -- "$B/test_app" --gtest_filter='Golden*'
rm -f /tmp/fovsim_isa_$$.log
echo "ISA paths exercised: embree {$(echo $isas | tr ' ' ',')} simd {$(echo $simds | tr ' ' ',')} libm {native,sse2}${failures:+; failed:$failures}"
echo "isa: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
