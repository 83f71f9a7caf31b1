// A GPU profile (DESIGN §6): spec-sheet throughputs, per-pass linear coefficients (ms per
// counter unit, see docs/cost_model.md for every term) plus a fixed overhead per pass, and
// the calibration residuals the coefficients were fitted with. Files: models/gpus/NAME.json,
// written by `fovsim calibrate`.
#pragma once
#include <map>
#include <string>
#include <vector>

#include "sim/core/params.h"

namespace fovsim {

// Resource classes a term loads; what-if scaling (`fovsim budget`) divides every coefficient
// of a class by the throughput factor.
enum class Resource { Geometry, Raster, Shading, Memory, Fixed };
const char* resource_name(Resource r);
Resource resource_from_name(const std::string& s, const std::string& where);

// Spec-sheet peak rates (boost clock), the normalisation of the cross-GPU fit.
struct GpuSpec {
  double fp32_gflops = 0;  // shading
  double mem_gbps = 0;     // memory bandwidth, GB/s
  double fill_gpix = 0;    // ROP fill rate, Gpixel/s (raster)
  double tri_gtris = 0;    // primitive rate, Gtriangles/s (geometry)
  double boost_mhz = 0;
  std::string source;
  // Peak rate of a class in units per millisecond (flop, byte, pixel, triangle).
  double rate_per_ms(Resource r) const;
};

struct PassCoef {
  double overhead_ms = 0;
  std::map<std::string, double> terms;  // term name -> ms per unit
};

struct CalibrationResidual {
  std::string id;       // calibration entry id
  double published_ms = 0, model_ms = 0, rel_err = 0;
};

struct GpuProfile {
  std::string name;
  std::string description;
  Json data;  // the profile document as loaded
  GpuSpec spec;
  std::map<std::string, PassCoef> passes;
  std::vector<CalibrationResidual> residuals;
  bool calibrated = false;  // false: coefficients transferred from the fit through spec ratios only

  // `name_or_path`: a file path (contains '/' or ends in .json) or a name in
  // models_dir/gpus/NAME.json. Throws fovsim::Error naming the file and JSON path.
  static GpuProfile load(const std::string& name_or_path, const std::string& models_dir);
  static GpuProfile from_json(const Json& j, const std::string& file);
  Json to_json() const;
  // Lists profile names found in models_dir/gpus.
  static std::vector<std::string> available(const std::string& models_dir);

  // What-if: throughput of `r` multiplied by `factor` (> 0): its coefficients divide by it.
  GpuProfile scaled(Resource r, double factor) const;
  // Coefficient of (pass, term) in ms per unit; 0 when absent.
  double coef(const std::string& pass, const std::string& term) const;
};

}  // namespace fovsim
