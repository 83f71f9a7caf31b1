#include "sim/trace/csv_table.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>

#include "sim/core/error.h"
#include "sim/core/files.h"

namespace fovsim {

static bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r';
}

std::vector<CsvField> split_csv_line(const std::string& line, char delim, const std::string& file,
                                     long line_no) {
  std::vector<CsvField> out;
  size_t i = 0, n = line.size();
  while (true) {
    CsvField f;
    // Leading spaces (but a tab delimiter is never trimmed away).
    while (i < n && is_space(line[i]) && line[i] != delim) ++i;
    f.col = int(i) + 1;
    if (i < n && line[i] == '"') {
      size_t q = i++;
      bool closed = false;
      while (i < n) {
        if (line[i] == '"') {
          if (i + 1 < n && line[i + 1] == '"') {
            f.text += '"';
            i += 2;
            continue;
          }
          closed = true;
          ++i;
          break;
        }
        f.text += line[i++];
      }
      if (!closed)
        throw Error(file_location(file, line_no, long(q) + 1), "unterminated quoted field");
      while (i < n && is_space(line[i]) && line[i] != delim) ++i;
      if (i < n && line[i] != delim)
        throw Error(file_location(file, line_no, long(i) + 1),
                    "unexpected text after a quoted field");
    } else {
      size_t s = i;
      while (i < n && line[i] != delim) ++i;
      size_t e = i;
      while (e > s && is_space(line[e - 1]) && line[e - 1] != delim) --e;
      f.text = line.substr(s, e - s);
    }
    out.push_back(std::move(f));
    if (i >= n) break;
    ++i;  // skip the delimiter; a trailing delimiter yields a final empty field
    if (i == n) {
      CsvField last;
      last.col = int(n) + 1;
      out.push_back(last);
      break;
    }
  }
  return out;
}

CsvReader::CsvReader(const std::string& path, char delim, char comment)
    : path_(path), text_(read_file(path)), delim_(delim), comment_(comment) {
  skip_bom();
}

CsvReader::CsvReader(FromText, std::string text, const std::string& name, char delim, char comment)
    : path_(name), text_(std::move(text)), delim_(delim), comment_(comment) {
  skip_bom();
}

CsvReader CsvReader::from_text(std::string text, const std::string& name, char delim,
                               char comment) {
  return CsvReader(FromText{}, std::move(text), name, delim, comment);
}

void CsvReader::skip_bom() {
  if (text_.size() >= 3 && (unsigned char)text_[0] == 0xEF && (unsigned char)text_[1] == 0xBB &&
      (unsigned char)text_[2] == 0xBF)
    pos_ = 3;
}

size_t CsvReader::lines_left() const {
  size_t n = 1;
  for (size_t i = pos_; i < text_.size(); ++i)
    n += text_[i] == '\n' || (text_[i] == '\r' && (i + 1 == text_.size() || text_[i + 1] != '\n'));
  return n;
}

bool CsvReader::next(CsvRow& r) {
  while (pos_ < text_.size()) {
    // Universal newlines: \n, \r\n and a lone \r (classic Mac / some exporters) end a line.
    size_t e = text_.find_first_of("\r\n", pos_);
    if (e == std::string::npos) e = text_.size();
    std::string line = text_.substr(pos_, e - pos_);
    pos_ = e + 1;
    if (e < text_.size() && text_[e] == '\r' && pos_ < text_.size() && text_[pos_] == '\n') ++pos_;
    ++line_no_;
    size_t k = 0;
    while (k < line.size() && (line[k] == ' ' || line[k] == '\t')) ++k;
    if (k == line.size()) continue;
    if (comment_ && line[k] == comment_) continue;
    r.line = line_no_;
    r.fields = split_csv_line(line, delim_, path_, line_no_);
    r.unterminated = e >= text_.size();
    return true;
  }
  return false;
}

bool looks_truncated(const CsvRow& last, const CsvRow* prev, size_t nfields, std::string& why) {
  if (!last.unterminated || last.fields.empty()) return false;
  if (last.fields.size() < nfields) {
    why = "the file's last line " + std::to_string(last.line) + " has " +
          std::to_string(last.fields.size()) + " of " + std::to_string(nfields) +
          " fields and no final newline: the file looks cut off (an interrupted write)";
    return true;
  }
  if (!prev || prev->fields.size() < last.fields.size()) return false;
  size_t k = last.fields.size() - 1;
  auto decimals = [](const std::string& t) {
    size_t d = t.find('.');
    if (d == std::string::npos) return 0;
    size_t n = 0;
    for (size_t i = d + 1; i < t.size() && std::isdigit((unsigned char)t[i]); ++i) ++n;
    return int(n);
  };
  const std::string &a = last.fields[k].text, &b = prev->fields[k].text;
  if (decimals(a) < decimals(b)) {
    why = "the file's last line " + std::to_string(last.line) + " ends in \"" + printable(a) +
          "\" with no final newline, where line " + std::to_string(prev->line) + " has \"" +
          printable(b) + "\": the file looks cut off inside its last field";
    return true;
  }
  return false;
}

std::vector<CsvRow> read_csv_rows(const std::string& path, char delim, char comment) {
  CsvReader rd(path, delim, comment);
  std::vector<CsvRow> rows;
  CsvRow r;
  while (rd.next(r)) rows.push_back(std::move(r));
  return rows;
}

std::string printable(const std::string& text, size_t max_len) {
  return escape_control(text, max_len);
}

bool parse_number(const std::string& text, double& out, std::string& why) {
  if (text.empty()) {
    why = "empty field";
    return false;
  }
  const char* b = text.data();
  const char* e = b + text.size();
  if (*b == '+') ++b;  // from_chars rejects a leading '+'
  double v = 0;
  auto r = std::from_chars(b, e, v);
  if (r.ec == std::errc::result_out_of_range) {
    why = "number out of range: \"" + printable(text) + "\"";
    return false;
  }
  if (r.ec != std::errc() || r.ptr != e) {
    why = "not a number: \"" + printable(text) + "\"";
    return false;
  }
  if (!std::isfinite(v)) {
    why = "non-finite value \"" + printable(text) + "\"";
    return false;
  }
  out = v;
  return true;
}

}  // namespace fovsim
