// Short citations of the papers fovsim implements, for user-facing text (docs tables, --help):
// "seed 004 §2.1" in a method declaration prints as "Meng 2018 §2.1". Full references:
// README.md "References".
#pragma once
#include <string>

namespace fovsim {

inline std::string cite_papers(std::string s) {
  static const char* kCites[][2] = {{"seed 001", "Yang et al. 2021"},
                                    {"seed 002", "Franke et al. 2021"},
                                    {"seed 003", "Ye et al. 2022"},
                                    {"seed 004", "Meng 2018"}};
  for (auto& c : kCites)
    for (size_t at = s.find(c[0]); at != std::string::npos; at = s.find(c[0], at))
      s.replace(at, 8, c[1]);
  return s;
}

}  // namespace fovsim
