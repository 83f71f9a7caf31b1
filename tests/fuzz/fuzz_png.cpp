// libFuzzer target: image files given to `compare` (PNG headers and bodies), through
// read_ldr_rgb: the header's size is checked against the limit before anything is decoded.
// Every failure must be a fovsim::Error; anything else is a bug. Build: `make fuzz`.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "sim/core/error.h"
#include "sim/metrics/compare.h"

using namespace fovsim;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  ::setenv("FOVSIM_MAX_IMAGE_MPIXELS", "4", 1);  // within libFuzzer's -rss_limit_mb
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path = (std::filesystem::temp_directory_path() /
                                   ("fovsim_fuzz_png_" + std::to_string(::getpid()) + ".png"))
                                      .string();
  {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  }
  try {
    Image img = read_ldr_rgb(path);
    (void)img.pixels();
  } catch (const Error&) {
  }
  return 0;
}
