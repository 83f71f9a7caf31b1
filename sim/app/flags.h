// The one reader of numeric command-line flags (docs/architecture.md "… a command"). Every numeric
// flag of every command is declared with add_number(), which attaches the one check a config key
// gets (check_number / check_integer, sim/core/params.h: NaN, infinities and values outside
// the range fail with "--flag: value V is out of range R") and writes the range and unit into
// --help ("FLOAT in [1, 86400] s"). tests/app/flags_test.cpp walks every command's options and
// fails on a numeric option declared any other way.
#pragma once
#include <CLI/CLI.hpp>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "sim/core/params.h"

namespace fovsim::app {

// Name of the validator add_number attaches (what the test looks for).
inline constexpr const char* kCheckedNumber = "fovsim-number";

// What a numeric flag accepts: a range, the unit shown in --help ("s", "Hz", "ms", "px",
// "fraction", "count", "factor"), and optionally 0 outside the range with a meaning ("off").
struct NumberFlag {
  // {range, unit[, integer[, zero]]} at every add_number call (a constructor, so the short
  // forms do not leave members to -Wmissing-field-initializers).
  NumberFlag(Range r, std::string u, bool is_integer = false, std::string zero_means = "")
      : range(r), unit(std::move(u)), integer(is_integer), zero(std::move(zero_means)) {}
  Range range;
  std::string unit;
  bool integer = false;
  std::string zero;  // non-empty: 0 is accepted too and means this
};

// "[1, 86400] s (0: off)": the range and unit as --help and error messages show them.
std::string number_flag_text(const NumberFlag& f);
// Checks one value as written: "" when it is accepted (an integer flag's text is rewritten to
// its plain digits, so "1e3" reads as 1000), else the error message.
std::string check_number_flag(std::string& text, const NumberFlag& f);

template <class T>
struct flag_element {
  using type = T;
};
template <class T>
struct flag_element<std::vector<T>> {
  using type = T;
};

// Declares a numeric option (a number, an integer or a list of them) through the check above.
template <class T>
CLI::Option* add_number(CLI::App* c, const std::string& names, T& var, const std::string& help,
                        NumberFlag f) {
  using E = typename flag_element<T>::type;
  static_assert(std::is_arithmetic_v<E> && !std::is_same_v<E, bool>, "a numeric member");
  if constexpr (std::is_integral_v<E>) f.integer = true;
  CLI::Option* o = c->add_option(names, var, help);
  const std::string text = number_flag_text(f);
  o->type_name(std::string(f.integer ? "INT" : "FLOAT") + " in " + text);
  o->check(
      CLI::Validator([f](std::string& s) { return check_number_flag(s, f); }, "", kCheckedNumber));
  return o;
}

}  // namespace fovsim::app
