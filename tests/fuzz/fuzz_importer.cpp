// libFuzzer target: importer column map + recording -> import_trace, under
// both bad-row policies and every FOV policy. The input is "<map JSON>\n%%\n<recording>"; an
// input without the "\n%%\n" separator is a recording read with a fixed comma-separated map
// (integer nanosecond times, so the exact integer rebasing is exercised). Every failure must
// be a fovsim::Error; any other exception, a crash or a sanitizer report is a bug.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <string>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/trace/importer.h"
#include "sim/trace/trace.h"

using namespace fovsim;

namespace {

const char* kDefaultMap = R"({"delimiter": "comma", "header": true, "coordinates": "fovsim",
  "on_bad_row": "skip", "max_skipped_fraction": 1,
  "time": {"column": "t", "unit": "ns", "wrap_bits": 62, "on_burst": "retime"},
  "head_position": {"columns": ["px", "py", "pz"], "unit": "cm"},
  "head_orientation": {"type": "quaternion", "columns": ["qw", "qx", "qy", "qz"]},
  "gaze": {"type": "direction", "space": "head", "columns": ["gx", "gy", "gz"]},
  "valid": [{"column": "v", "all_bits": 3}]})";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string pid = std::to_string(::getpid());
  static const std::string map_path = "/tmp/fovsim_fuzz_importer_map_" + pid + ".json";
  static const std::string rec_path = "/tmp/fovsim_fuzz_importer_rec_" + pid + ".csv";
  static Display display = [] {
    Params p(Json{{"width", 64},
                  {"height", 72},
                  {"fov_h_deg", 100},
                  {"fov_v_deg", 110},
                  {"refresh_hz", 90}},
             "display");
    return Display::from_params(p);
  }();
  std::string text(reinterpret_cast<const char*>(data), size);
  size_t sep = text.find("\n%%\n");
  if (sep == std::string::npos) {
    write_file_atomic(map_path, kDefaultMap);
    write_file_atomic(rec_path, text);
  } else {
    write_file_atomic(map_path, text.substr(0, sep));
    write_file_atomic(rec_path, text.substr(sep + 4));
  }
  for (auto pol : {BadSamplePolicy::Fail, BadSamplePolicy::Skip, BadSamplePolicy::Hold}) {
    try {
      ImportOptions opt;
      opt.on_fov = pol;
      opt.check_fov = pol != BadSamplePolicy::Hold || size % 2;
      if (pol == BadSamplePolicy::Skip) opt.stop_after_s = 1.0;
      ImportReport rep;
      Trace tr = import_trace(rec_path, map_path, display, &rep, opt);
      if (!tr.samples.empty() && resampled_count(tr, 90.0, tr.samples.front().t + 2.0) < 1e6)
        (void)resample(tr, 90.0, tr.samples.front().t + 2.0);
    } catch (const Error&) {
    }
  }
  return 0;
}
