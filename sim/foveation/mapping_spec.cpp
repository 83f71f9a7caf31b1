#include "sim/foveation/mapping_spec.h"

#include "sim/core/error.h"
#include "sim/core/param_table.h"
#include "sim/foveation/factory.h"

namespace fovsim {

MappingSpec read_mapping_spec(const SamplingGeometry& g, Params& p) {
  MappingSpec s;
  s.method = g.method;
  s.geometry = &g;
  g.params().read_into(p, s);
  return s;
}

MappingSpec MappingSpec::from_params(const std::string& method, Params& p) {
  const auto m = make_method(method, p);
  if (!m->mapping_spec()) p.fail("method", "not a mapping method: \"" + method + "\"");
  return *m->mapping_spec();
}

void add_radius_rows(ParamTable<MappingSpec>& t, const char* source, const char* r1_doc,
                     const char* r2_doc) {
  t.number("r1", 10.0, Range::closed(0, 180), &MappingSpec::r1)
      .doc(source, r1_doc)
      .column("r1", [](const MappingSpec& s) { return s.r1_eff(); })
      .number("r2", 20.0, Range::closed(0, 180), &MappingSpec::r2)
      .doc(source, r2_doc)
      .shown("20", "[r1, 180]")
      .column("r2", [](const MappingSpec& s) { return s.r2_eff(); })
      .number("radius_scale", 1.0, Range::above(0), &MappingSpec::radius_scale)
      .doc("iso-budget", "multiplies r1 and r2")
      .column()
      .validate([](const MappingSpec& s, Params& p) {
        if (s.r2 < s.r1) p.fail("r2", "must be >= r1 (" + std::to_string(s.r1) + ")");
      });
}

void add_target_row(ParamTable<MappingSpec>& t, const char* free) {
  t.number("target_shaded_fraction", 0, Range::above(0, 1), &MappingSpec::target_shaded_fraction)
      .optional()
      .doc("Ye et al. 2022 §5.1", (std::string("iso-budget: solve ") + free).c_str())
      .column(nullptr, {}, [](const MappingSpec& s) { return s.target_shaded_fraction > 0; });
}

std::vector<std::pair<std::string, std::string>> MappingSpec::text_columns() const {
  return geometry ? geometry->params().text_columns(*this)
                  : std::vector<std::pair<std::string, std::string>>{};
}

std::vector<std::pair<std::string, double>> MappingSpec::columns() const {
  return geometry ? geometry->params().columns(*this)
                  : std::vector<std::pair<std::string, double>>{};
}

}  // namespace fovsim
