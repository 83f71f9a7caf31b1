// The text descriptor of one declared parameter, and a forward declaration of the table that
// declares it (sim/core/param_table.h), for headers that only name them.
#pragma once

namespace fovsim {

// Descriptor of one parameter as text (what docs and `fovsim methods` print).
struct ParamInfo {
  const char* name;
  const char* type;
  const char* def;
  const char* range;
  const char* source;  // paper section the value or the rule comes from
  const char* doc;
};

template <class T>
class ParamTable;

}  // namespace fovsim
