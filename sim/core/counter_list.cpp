// Column-name lookup and the generated documentation of the counter list (counter_list.h).
#include "sim/core/counter_list.h"

#include <cctype>

namespace fovsim {

std::optional<CounterKey> find_counter(std::string_view name) {
  for (int i = 0; i < kCounterCount; ++i) {
    const Counter c = Counter(i);
    const std::string_view n = counter_name(c);
    if (!counter_indexed(c)) {
      if (name == n) return CounterKey{c};
      continue;
    }
    // holes_mip<k>: the family name followed by a decimal index.
    if (name.size() <= n.size() || name.substr(0, n.size()) != n) continue;
    const std::string_view digits = name.substr(n.size());
    if (digits.size() > 6) continue;
    int k = 0;
    bool ok = true;
    for (char ch : digits) {
      if (!std::isdigit(static_cast<unsigned char>(ch))) ok = false;
      k = k * 10 + (ch - '0');
    }
    if (ok) return CounterKey{c, k};
  }
  return std::nullopt;
}

std::string counters_markdown() {
  std::string s =
      "| counter | unit | scales to the display | meaning |\n"
      "|---|---|---|---|\n";
  for (int i = 0; i < kCounterCount; ++i) {
    const CounterInfo& c = counter_info(Counter(i));
    const char* scale = c.scale == CounterScale::Pixels       ? "× pixel_scale"
                        : c.scale == CounterScale::Primitives ? "no (primitives)"
                                                              : "no (fixed)";
    s += std::string("| `") + c.name + (counter_indexed(Counter(i)) ? "<k>" : "") + "` | " +
         c.unit + " | " + scale + " | " + c.doc + " |\n";
  }
  return s;
}

}  // namespace fovsim
