#include "sim/foveation/mapping_spec.h"

#include "sim/core/error.h"
#include "sim/foveation/factory.h"

namespace fovsim {

MappingSpec read_mapping_spec(std::unique_ptr<SamplingGeometry> g, Params& p) {
  MappingSpec s(std::move(g));
  // Every member starts from its row's default (also one a read_if leaves unread): the
  // geometry structs write no default of their own.
  for (const auto& r : s.geometry().table().rows())
    if (!r.doc_only && !r.member_default && !r.def.is_null()) r.set(s, r.def);
  s.geometry().table().read_into(p, s);
  return s;
}

MappingSpec MappingSpec::from_params(const std::string& method, Params& p) {
  const auto m = make_method(method, p);
  if (!m->mapping_spec()) p.fail("method", "not a mapping method: \"" + method + "\"");
  return *m->mapping_spec();
}

void add_target_row(ParamTable<MappingSpec>& t, const char* free) {
  t.number("target_shaded_fraction", 0, Range::above(0, 1),
           field<SamplingGeometry>(&SamplingGeometry::target_shaded_fraction))
      .optional()
      .doc("Ye et al. 2022 §5.1", (std::string("iso-budget: solve ") + free).c_str())
      .column(nullptr, {}, [](const MappingSpec& s) { return s.target_shaded_fraction() > 0; });
}

std::vector<std::pair<std::string, std::string>> MappingSpec::text_columns() const {
  return g_ ? g_->table().text_columns(*this) : std::vector<std::pair<std::string, std::string>>{};
}

std::vector<std::pair<std::string, double>> MappingSpec::columns() const {
  return g_ ? g_->table().columns(*this) : std::vector<std::pair<std::string, double>>{};
}

}  // namespace fovsim
