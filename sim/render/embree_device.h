// Which Embree code path (ISA) runs, and how to force one from the outside (issue: results
// must not depend on the CPU). Embree 3 picks its kernels per CPU (SSE2 ... AVX-512); the
// environment variable FOVSIM_EMBREE_ISA forces one of them for every Embree device fovsim
// creates, so the test suite can run each path a machine supports (tests/isa/run_isa_tests.sh).
#pragma once
#include <string>
#include <vector>

namespace fovsim {

// Embree 3's ISA names as accepted by rtcNewDevice's "isa=" option, lowest first.
const std::vector<std::string>& embree_isa_names();
// The ISAs this CPU can run (a prefix of embree_isa_names(); sse2 is always there on x86-64).
std::vector<std::string> embree_supported_isas();
// The ISA forced by FOVSIM_EMBREE_ISA ("" when unset or "native"). Throws Error naming the
// variable, the allowed values and what this CPU supports when the value is unknown or the
// CPU cannot run it.
std::string embree_forced_isa();
// The ISA Embree runs here: the forced one, else the best this CPU supports.
std::string embree_active_isa();
// The config string for rtcNewDevice ("" = Embree's default choice).
std::string embree_device_config();

}  // namespace fovsim
