// How fovsim's run-time-dispatched lane kernels (G-buffer, tone map, FovVideoVDP's powers,
// texture box filters) pick their width: one rule for all of them. The instruction set a kernel
// may use is FOVSIM_SIMD=generic -> SSE2, =avx2 -> AVX2 where the CPU has it, otherwise (unset
// or native) the widest the CPU has; each kernel states its width per instruction set.
#pragma once
#include <atomic>

// Whether kernels compiled twice (a generic copy and one with __attribute__((target("avx2"))),
// dispatched at run time) get their AVX2 copy: GCC on x86-64.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define FOVSIM_HAVE_AVX2_PATH 1
#else
#define FOVSIM_HAVE_AVX2_PATH 0
#endif

namespace fovsim {

enum class LaneIsa { sse2 = 0, avx2 = 1, avx512f = 2 };

// Whether this CPU (and OS) runs the instruction set; SSE2 always.
bool cpu_has(LaneIsa isa);
// The instruction set the kernels may use, from FOVSIM_SIMD and the CPU (read once).
LaneIsa auto_lane_isa();

// One kernel's lanes per instruction on each instruction set ({SSE2, AVX2, AVX-512F}; a kernel
// that gains nothing from an ISA repeats the narrower width), and a width forced by tests.
class LaneChoice {
 public:
  constexpr LaneChoice(int sse2, int avx2, int avx512f) : w_{sse2, avx2, avx512f} {}
  // The forced width, else the automatic one (auto_lane_isa's entry).
  int width() const;
  // 0: automatic; a width of an instruction set this CPU runs; any other value: the SSE2 width.
  void force(int w);
  // Whether this CPU runs width w (some instruction set it has uses it).
  bool runs(int w) const;

 private:
  int w_[3];
  std::atomic<int> forced_{0};
};

}  // namespace fovsim
