// Every numeric flag of every command goes through the one checked reader (sim/app/flags.h):
// the walk below registers the commands as main.cpp does and fails on a numeric option declared
// any other way, on one whose --help does not show its range and unit, and on one that accepts
// NaN, an infinity or a value past any range.
#include "sim/app/flags.h"

#include <gtest/gtest.h>

#include <functional>
#include <regex>
#include <string>
#include <vector>

#include "sim/app/commands.h"

namespace {

struct NumericOption {
  std::vector<std::string> command;  // "trace", "synth"
  std::string flag;                  // "--duration"
  std::string type;                  // its --help type text
  bool checked = false;
};

bool numeric_type(const std::string& t) {
  for (const char* p : {"INT", "UINT", "FLOAT", "NUMBER"}) {
    const std::string s = p;
    if (t.compare(0, s.size(), s) == 0 &&
        (t.size() == s.size() || t[s.size()] == ' ' || t[s.size()] == ':'))
      return true;
  }
  return false;
}

std::string flag_name(const CLI::Option* o) {
  if (!o->get_lnames().empty()) return "--" + o->get_lnames().front();
  if (!o->get_snames().empty()) return "-" + o->get_snames().front();
  return o->get_name();
}

std::vector<NumericOption> numeric_options() {
  CLI::App app;
  fovsim::app::Action action;
  fovsim::app::register_commands(app, action);
  std::vector<NumericOption> out;
  std::function<void(CLI::App*, std::vector<std::string>)> walk =
      [&](CLI::App* a, std::vector<std::string> path) {
        for (CLI::Option* o : a->get_options()) {
          if (o->get_items_expected_max() == 0) continue;  // a flag without a value
          const std::string type = o->get_type_name();
          if (!numeric_type(type)) continue;
          NumericOption n{path, flag_name(o), type, false};
          try {
            n.checked = o->get_validator(fovsim::app::kCheckedNumber) != nullptr;
          } catch (const CLI::OptionNotFound&) {
          }
          out.push_back(n);
        }
        for (CLI::App* s : a->get_subcommands({})) {
          std::vector<std::string> p = path;
          p.push_back(s->get_name());
          walk(s, p);
        }
      };
  walk(&app, {});
  return out;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (auto& x : v) s += (s.empty() ? "" : " ") + x;
  return s;
}

}  // namespace

TEST(Flags, EveryNumericOptionOfEveryCommandIsChecked) {
  const std::vector<NumericOption> opts = numeric_options();
  // The commands have numeric flags (the walk found them): run, budget, density, trace synth...
  ASSERT_GT(opts.size(), 25u);
  // "FLOAT in [0.05, 0.99] probability", "INT in [1, 360] directions", "... (0: off)".
  const std::regex shown(R"(^(INT|FLOAT) in [\[(][^,]+, [^\])]+[\])] [^ ].*$)");
  for (const NumericOption& o : opts) {
    const std::string where = join(o.command) + " " + o.flag;
    EXPECT_TRUE(o.checked) << where << " (" << o.type
                           << "): declare numeric flags with add_number (sim/app/flags.h)";
    EXPECT_TRUE(std::regex_match(o.type, shown))
        << where << ": --help shows \"" << o.type << "\", not its range and unit";
  }
}

TEST(Flags, EveryNumericOptionRefusesNanInfinityAndHugeValues) {
  for (const NumericOption& o : numeric_options()) {
    for (const char* v : {"nan", "inf", "-inf", "1e308", "-1e308", "abc"}) {
      CLI::App app;
      fovsim::app::Action action;
      fovsim::app::register_commands(app, action);
      std::vector<std::string> args = o.command;
      args.push_back(o.flag);
      args.push_back(v);
      std::vector<std::string> rev(args.rbegin(), args.rend());  // CLI11 parses a reversed list
      const std::string where = join(args);
      try {
        app.parse(rev);
        ADD_FAILURE() << where << ": accepted";
      } catch (const CLI::ValidationError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find(o.flag), std::string::npos) << where << ": " << msg;
        EXPECT_TRUE(msg.find("out of range") != std::string::npos ||
                    msg.find("is not a number") != std::string::npos ||
                    msg.find("is not an integer") != std::string::npos)
            << where << ": " << msg;
      } catch (const CLI::ParseError& e) {
        ADD_FAILURE() << where << ": not the range check: " << e.what();
      }
    }
  }
}

TEST(Flags, CheckNamesTheValueRangeAndUnit) {
  using fovsim::app::NumberFlag;
  NumberFlag wd{fovsim::Range::closed(1, 86400), "s", false, "off"};
  std::string t = "1e-300";
  EXPECT_EQ(fovsim::app::check_number_flag(t, wd),
            "value 1e-300 is out of range [1, 86400] s (0: off)");
  t = "0";
  EXPECT_EQ(fovsim::app::check_number_flag(t, wd), "");
  NumberFlag p{fovsim::Range::above(0, 4), "fraction"};
  t = "4.0000001";  // printed as given, not as "4"
  EXPECT_EQ(fovsim::app::check_number_flag(t, p),
            "value 4.0000001 is out of range (0, 4] fraction");
  NumberFlag n{fovsim::Range::closed(1, 360), "directions", true};
  t = "1e2";  // an integer written as a float reads as its digits
  EXPECT_EQ(fovsim::app::check_number_flag(t, n), "");
  EXPECT_EQ(t, "100");
  t = "2.5";
  EXPECT_EQ(fovsim::app::check_number_flag(t, n),
            "value 2.5 is not an integer in [1, 360] directions");
}
