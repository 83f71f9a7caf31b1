// ParamTable (sim/core/param_table.h): one row per key drives parsing with located errors,
// defaults, ranges, cross-key rules, columns and docs.
#include "sim/core/param_table.h"

#include <gtest/gtest.h>

#include "sim/core/error.h"
#include "tests/common/param_table_check.h"

using namespace fovsim;

namespace {
enum class Mode { A, B };
struct Toy {
  double x = 0;
  float f = 0;
  int n = 0;
  bool on = false;
  std::string s;
  Mode mode = Mode::A;
  std::vector<double> edges;
  double opt = -1, lo = 0, hi = 0;
};

const ParamTable<Toy>& toy_table() {
  static const auto t =
      ParamTable<Toy>()
          .number("x", 1.5, Range::closed(0, 10), &Toy::x)
          .doc("Meng 2018 §2.1", "a number")
          .column()
          .number("f", 0.1, Range::above(0, 1), &Toy::f)
          .doc("", "a float member")
          .integer("n", 3, Range::closed(1, 64), &Toy::n)
          .doc("", "an integer")
          .column("n_col")
          .boolean("on", true, &Toy::on)
          .doc("", "a flag")
          .text("s", "abc", {}, &Toy::s)
          .doc("", "free text")
          .column()
          .choice("mode", "b",
                  std::vector<std::pair<std::string, Mode>>{{"a", Mode::A}, {"b", Mode::B}},
                  &Toy::mode)
          .doc("", "an option")
          .numbers("edges", {0, 5}, Range::closed(0, 180), &Toy::edges)
          .doc("", "numbers")
          .number("opt", 0, Range::above(0), &Toy::opt)
          .optional()
          .doc("", "read only when given")
          .column(nullptr, {}, [](const Toy& t) { return t.opt > 0; })
          .number("lo", 1, Range::closed(0, 100), &Toy::lo)
          .doc("", "lower")
          .number("hi", 2, Range::closed(0, 100), &Toy::hi)
          .doc("", "upper")
          .shown("2", "[lo, 100]")
          .validate([](const Toy& t, Params& p) {
            if (t.hi < t.lo) p.fail("hi", "must be >= lo");
          });
  return t;
}
}  // namespace

TEST(ParamTable, ReadsItsOwnDefaults) {
  table_check::expect_table_reads_own_defaults(toy_table(), "toy");
  Params p(Json::object(), "t.json", "toy");
  const Toy t = toy_table().read(p);
  EXPECT_EQ(t.x, 1.5);
  EXPECT_EQ(t.f, 0.1f);
  EXPECT_EQ(t.n, 3);
  EXPECT_TRUE(t.on);
  EXPECT_EQ(t.s, "abc");
  EXPECT_EQ(t.mode, Mode::B);
  EXPECT_EQ(t.edges, (std::vector<double>{0, 5}));
  EXPECT_EQ(t.opt, -1);  // optional, not given: the member keeps its value
  // Every read (defaults included) is in the resolved document; the optional key is not.
  EXPECT_EQ(p.resolved()["x"], 1.5);
  EXPECT_FALSE(p.resolved().contains("opt"));
}

TEST(ParamTable, ErrorsAreLocatedLikeParams) {
  auto err = [](Json j) {
    Params p(std::move(j), "run.json", "methods[1]");
    try {
      toy_table().read(p);
      p.finish();
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(err({{"x", 11}}), "run.json: methods[1].x: value 11 is out of range [0, 10]");
  EXPECT_NE(err({{"mode", "c"}}).find("methods[1].mode"), std::string::npos);
  EXPECT_NE(err({{"n", 2.5}}).find("methods[1].n"), std::string::npos);
  EXPECT_EQ(err({{"lo", 5}, {"hi", 4}}), "run.json: methods[1].hi: must be >= lo");
  EXPECT_NE(err({{"xx", 1}}).find("unknown key \"xx\""), std::string::npos);
}

TEST(ParamTable, ColumnsAndDocs) {
  Params p(Json{{"opt", 2.0}}, "t", "");
  const Toy t = toy_table().read(p);
  const auto c = toy_table().columns(t);
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c[0], (std::pair<std::string, double>{"x", 1.5}));
  EXPECT_EQ(c[1], (std::pair<std::string, double>{"n_col", 3}));
  EXPECT_EQ(c[2], (std::pair<std::string, double>{"opt", 2}));
  EXPECT_EQ(toy_table().text_columns(t),
            (std::vector<std::pair<std::string, std::string>>{{"s", "abc"}}));
  const std::string md = toy_table().markdown();
  EXPECT_NE(md.find("| `x` | number | 1.5 | [0, 10] | Meng 2018 §2.1 | a number |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| `mode` | string | b | a \\| b |"), std::string::npos) << md;
  EXPECT_NE(md.find("| `opt` | number | none | (0, inf) |"), std::string::npos) << md;
  EXPECT_NE(md.find("| `hi` | number | 2 | [lo, 100] |"), std::string::npos) << md;
  EXPECT_EQ(param_doc_number(5e7), "5e7");
  EXPECT_EQ(param_doc_number(1e-5), "1e-5");
  EXPECT_EQ(param_doc_number(0.047), "0.047");
}
