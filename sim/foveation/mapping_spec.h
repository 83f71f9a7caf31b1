// Parameters and sampling geometry of the image-mapping methods (kfr, rmfr) and the baselines
// (hyperbolic, linear, fvrs). Each method's own file defines its SamplingGeometry: a struct of
// its parameters (sigma and the kernel for kfr; f_x, f_y for rmfr; r1, r2 and layer sizes for
// hyperbolic; ...) read through its ParamTable<MappingSpec>, with the density at a pixel, the
// expected shaded samples, the iso-budget's free parameter and how it widens under tracking
// loss. MappingSpec is the copyable handle the methods, the analytic density (`fovsim
// density`), the analytic counters of `predict` and the iso-budget solver pass around; none of
// them names a method. Adding a mapping method adds no field here (docs/architecture.md "… a
// method").
#pragma once
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "sim/core/image.h"
#include "sim/core/param_info.h"
#include "sim/core/param_table.h"
#include "sim/core/params.h"
#include "sim/foveation/mapping.h"  // parallel_rows
#include "sim/foveation/method_cost.h"
#include "sim/foveation/taa.h"

namespace fovsim {

class MappingSpec;
struct MappingView;  // density.h

// The free parameter the iso-budget solver varies (Ye et al. 2022 §5.1): its key, the search
// interval (searched on a log axis; the shaded fraction is monotone in it) and an optional
// closed form for a target fraction (nullptr: search), which returns false when the target is
// out of reach (the value is then the closest reachable one).
struct FreeParam {
  const char* key;
  double lo, hi;
  bool (*closed_form)(double target, double* value);
};

// The sampling geometry of one mapping method and the parameters it is computed from, defined
// in the method's file (kfr.cpp, ...) as a struct deriving GeometryOf<itself>. Virtual calls
// are per view or per frame; the per-pixel loops (density_image, the methods' render passes)
// run over the concrete struct.
class SamplingGeometry {
 public:
  virtual ~SamplingGeometry() = default;
  virtual const char* method() const = 0;
  virtual std::unique_ptr<SamplingGeometry> clone() const = 0;
  // The keys it reads (defaults, ranges, docs, frames.csv columns).
  virtual const ParamTable<MappingSpec>& table() const = 0;
  // Shading samples per screen pixel at screen point (x, y).
  virtual double density(const MappingView& v, double x, double y) const = 0;
  // Density at every pixel centre into d (v.W x v.H, 1 channel, allocated by the caller).
  virtual void density_image(const MappingView& v, Image& d) const = 0;
  // Samples the render pass shades for this view (exact, or the expected value).
  virtual double expected_samples(const MappingView& v) const = 0;
  // True when a whole (W / sigma) x (H / sigma) buffer is allocated and shaded (kfr, rmfr):
  // the analytic counters then charge the buffer, else the expected samples.
  virtual bool shades_whole_buffer() const = 0;
  // With shades_whole_buffer: the buffer's reduction per axis, W / w = H / h (kfr, rmfr: sigma);
  // the analytic counters charge (W / r) x (H / r) samples.
  virtual double buffer_reduction() const { return 1.0; }
  // The parameter `fovsim budget` may change first (method_cost.h; none by default).
  virtual BudgetKnob budget_knob() const { return {}; }
  // Iso-budget: the free parameter and the member holding its value.
  virtual FreeParam free_param() const = 0;
  virtual double& free_ref() = 0;
  double free_value() const { return const_cast<SamplingGeometry*>(this)->free_ref(); }
  // Tracking loss (FrameContext::widen = k > 1, docs/tracking.md): the geometry the method
  // renders with, changed in place. Default: unchanged (the baselines widen through the
  // eccentricity map, MappingView::widen).
  virtual void widen(double k) { (void)k; }
  // The same widening written as config keys, for the analytic cost of a lost frame
  // (`fovsim predict --tracking-loss`, which costs keys, not a render): sets in p the widened
  // value of every key the widening changes. Default: none.
  virtual void widen_keys(double k, Json& p) const { (void)k, (void)p; }

  // Shared by every mapping method: > 0 asks the iso-budget solver for this shaded fraction.
  double target_shaded_fraction = 0;
  // Its TAA post pass (taa.h): rows in the tables of the methods whose seed has one (kfr, rmfr).
  TaaSettings taa;
};

// Copyable handle of a method's SamplingGeometry (deep copy).
class MappingSpec {
 public:
  MappingSpec() = default;
  explicit MappingSpec(std::unique_ptr<SamplingGeometry> g) : g_(std::move(g)) {}
  MappingSpec(const MappingSpec& o) : g_(o.g_ ? o.g_->clone() : nullptr) {}
  MappingSpec& operator=(const MappingSpec& o) {
    if (this != &o) g_ = o.g_ ? o.g_->clone() : nullptr;
    return *this;
  }
  MappingSpec(MappingSpec&&) = default;
  MappingSpec& operator=(MappingSpec&&) = default;

  const SamplingGeometry& geometry() const { return *g_; }
  SamplingGeometry& geometry() { return *g_; }
  // The method's own parameter struct (the caller knows the method: its file, its table).
  template <class G>
  const G& as() const {
    return static_cast<const G&>(*g_);
  }
  template <class G>
  G& as() {
    return static_cast<G&>(*g_);
  }
  std::string method() const { return g_ ? g_->method() : ""; }
  double target_shaded_fraction() const { return g_ ? g_->target_shaded_fraction : 0; }

  // The spec of mapping method `method` as make_method reads it (tests; the methods read
  // theirs with read_mapping_spec); other methods are an error at `method`.
  static MappingSpec from_params(const std::string& method, Params& p);
  // Parameter columns for frames.csv (the geometry's table: sigma, alpha, fx, fy, r1, ...).
  std::vector<std::pair<std::string, double>> columns() const;
  // String parameters as written in the config (kfr: {"kernel", "power"}).
  std::vector<std::pair<std::string, std::string>> text_columns() const;

 private:
  std::unique_ptr<SamplingGeometry> g_;
};

// Reads geometry G's keys from p through its table (unknown keys are left for
// Params::finish()). Each member first takes its row's default, so a geometry struct's members
// start at zero and the table is the one place a default is written.
MappingSpec read_mapping_spec(std::unique_ptr<SamplingGeometry> g, Params& p);
template <class G>
MappingSpec read_mapping_spec(Params& p) {
  return read_mapping_spec(std::make_unique<G>(), p);
}

// The accessor of member `m` of geometry G inside a MappingSpec, for G's ParamTable rows:
//   t.number("sigma", 1.8, Range::at_least(1), field<KfrGeometry>(&KfrGeometry::sigma))
template <class G, class C, class M>
auto field(M C::*m) {
  return [m](auto& s) -> auto& {
    return s.template as<G>().*m;
  };
}

// CRTP base of a method's geometry struct G: clone, table, and the density image as a loop
// over G::density (no virtual call per pixel). G declares `static constexpr const char*
// kMethod` and `static const ParamTable<MappingSpec>& params_table()`.
template <class G>
class GeometryOf : public SamplingGeometry {
 public:
  const char* method() const override { return G::kMethod; }
  std::unique_ptr<SamplingGeometry> clone() const override {
    return std::make_unique<G>(static_cast<const G&>(*this));
  }
  const ParamTable<MappingSpec>& table() const override { return G::params_table(); }
  void density_image(const MappingView& v, Image& d) const override;
};

// G::density (not virtual) at every pixel centre, rows in parallel.
template <class G>
void GeometryOf<G>::density_image(const MappingView& v, Image& d) const {
  const G& g = static_cast<const G&>(*this);
  parallel_rows(d.height, [&](int y) {
    float* row = d.row(y);
    for (int x = 0; x < d.width; ++x) row[x] = float(g.G::density(v, x + 0.5, y + 0.5));
  });
}

// The eccentricity thresholds shared by the baselines (hyperbolic, linear, fvrs).
struct RadialThresholds {
  // Defaults: add_radius_rows (read_mapping_spec sets them).
  double r1 = 0, r2 = 0;    // eccentricity thresholds, degrees
  double radius_scale = 0;  // multiplies r1 and r2 (the iso-budget free parameter)
  double r1_eff() const { return r1 * radius_scale; }
  double r2_eff() const { return r2 * radius_scale; }
  // A render divides the frame's eccentricities by k (MappingView::widen); on the keys that is
  // radius_scale' = k radius_scale (SamplingGeometry::widen_keys of the baselines).
  void widen_radius_keys(double k, Json& p) const { p["radius_scale"] = radius_scale * k; }
};

// Rows shared by the baselines, in column order: r1, r2 (columns: the radius-scaled values),
// radius_scale, with the r2 >= r1 rule; G derives RadialThresholds. `source` cites the paper,
// r1_doc / r2_doc say what the radii bound.
template <class G>
void add_radius_rows(ParamTable<MappingSpec>& t, const char* source, const char* r1_doc,
                     const char* r2_doc) {
  t.number("r1", 10.0, Range::closed(0, 180), field<G>(&G::r1))
      .doc(source, r1_doc)
      .column("r1", [](const MappingSpec& s) { return s.as<G>().r1_eff(); })
      .number("r2", 20.0, Range::closed(0, 180), field<G>(&G::r2))
      .doc(source, r2_doc)
      .shown("20", "[r1, 180]")
      .column("r2", [](const MappingSpec& s) { return s.as<G>().r2_eff(); })
      .number("radius_scale", 1.0, Range::above(0), field<G>(&G::radius_scale))
      .doc("iso-budget", "multiplies r1 and r2")
      .column()
      .validate([](const MappingSpec& s, Params& p) {
        const G& g = s.as<G>();
        if (g.r2 < g.r1) p.fail("r2", "must be >= r1 (" + std::to_string(g.r1) + ")");
      });
}
// The optional target_shaded_fraction row (last: its column follows the others); `free`
// names the parameter the solver varies.
void add_target_row(ParamTable<MappingSpec>& t, const char* free);

}  // namespace fovsim
