// How messages print numbers and the JSON library's exceptions (defined in params.cpp, beside
// the checks that use them).
#pragma once
#include <exception>
#include <string>

namespace fovsim {

// The shortest text that reads back as `v` ("4.0000001", "1e+300", "0.1", "inf"): how error
// messages print values and bounds (Range::str, check_number, Params, the CLI's flags) -- a
// bound prints as given, never rounded to look equal to the value, and never as 300 digits.
std::string shortest_number(double v);

// The text of a JSON library exception without its "[json.exception.type_error.302] " tag
// ("type must be string, but is number"): what an error message may say of it.
std::string json_error_text(const std::exception& e);

}  // namespace fovsim
