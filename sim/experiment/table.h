// A small results table: text key columns + numeric columns in first-seen order, written as
// CSV with deterministic number formatting (%.10g; inf/nan spelled "inf"/"nan").
#pragma once
#include <string>
#include <utility>
#include <vector>

namespace fovsim {

struct ResultRow {
  std::vector<std::pair<std::string, std::string>> text;
  std::vector<std::pair<std::string, double>> num;
  void set_text(const std::string& k, const std::string& v);
  void set(const std::string& k, double v);
  double get(const std::string& k, double fallback) const;
  const std::string* text_of(const std::string& k) const;
};

class ResultTable {
 public:
  void add(ResultRow r);
  const std::vector<ResultRow>& rows() const { return rows_; }
  std::vector<std::string> text_columns() const;
  std::vector<std::string> numeric_columns() const;
  std::string to_csv() const;

 private:
  std::vector<ResultRow> rows_;
};

std::string format_number(double v);
// A CSV cell: quoted when it holds ',' or '"'; control bytes written as \\xNN.
std::string csv_escape(const std::string& s);

}  // namespace fovsim
