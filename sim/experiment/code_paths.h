// Which CPU-specific code paths this machine offers and which one runs (Embree's ISA and
// fovsim's own SIMD kernels). Results do not depend on them (tests/isa/run_isa_tests.sh);
// `fovsim info` prints this, manifests record the active pair.
#pragma once
#include "sim/core/params.h"

namespace fovsim {

// {"embree_isas": [...], "embree_isa": "...", "simd_paths": [...], "simd_path": "..."}.
// Throws Error when FOVSIM_EMBREE_ISA or FOVSIM_SIMD holds a bad value.
Json code_paths_info();

}  // namespace fovsim
