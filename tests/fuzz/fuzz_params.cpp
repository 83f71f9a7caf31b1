// libFuzzer target: JSON text -> parse_json_text -> Params getters and
// finish(), plus command-line overrides. Every failure must be a fovsim::Error; any other
// exception, a crash or a sanitizer report is a bug. Build: `make fuzz` (tests/fuzz/README.md).
#include <cstddef>
#include <cstdint>
#include <string>

#include "sim/core/error.h"
#include "sim/core/params.h"

using namespace fovsim;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string text(reinterpret_cast<const char*>(data), size);
  // First line: an override "key.path=value"; the rest: a config.
  size_t nl = text.find('\n');
  std::string ov = nl == std::string::npos ? "" : text.substr(0, nl);
  std::string cfg = nl == std::string::npos ? text : text.substr(nl + 1);
  try {
    (void)parse_value_or_string(ov, "fuzz");
  } catch (const Error&) {
  }
  try {
    Json doc = parse_json_text(cfg, "fuzz.json");
    if (!ov.empty()) apply_override(doc, ov);
    Params p(doc, "fuzz.json");
    p.ignore("comment");
    (void)p.number("x", 1.0, Range::above(0, 10));
    (void)p.integer("n", 1, Range::closed(0, 100));
    (void)p.string("s", "a", {"a", "b"});
    (void)p.boolean("b", false);
    (void)p.numbers("v", {}, Range::at_least(0));
    Params c = p.child("child");
    (void)c.number("y", 0.0);
    for (auto& e : p.children("list")) (void)e.integer("k", 0, Range::any());
    if (p.has("raw")) (void)p.raw("raw");
    p.finish();
    (void)p.resolved().dump(2);
  } catch (const Error&) {
  }
  return 0;
}
