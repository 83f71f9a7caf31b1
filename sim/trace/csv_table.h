// Line-oriented delimited-text reading shared by the canonical trace reader and the
// importer: every field keeps its 1-based line and character column so that errors can
// name file:line:column.
#pragma once
#include <string>
#include <vector>

namespace fovsim {

struct CsvField {
  std::string text;  // unquoted, surrounding spaces trimmed
  int col = 1;       // 1-based character column of the field's first character
};

struct CsvRow {
  long line = 0;  // 1-based line number in the file
  std::vector<CsvField> fields;
  bool unterminated = false;  // the file's last line, with no newline after it
};

// True when `last` (the file's last row, no final newline) looks cut off by an interrupted
// write: fewer fields than `nfields`, or its last field has fewer decimals than the same field
// of the row before (`prev`, may be null) -- "358.9176" cut to "358". Sets `why`.
bool looks_truncated(const CsvRow& last, const CsvRow* prev, size_t nfields, std::string& why);

// Splits one line (without its newline) on `delim`. Double-quoted fields may contain the
// delimiter; "" inside quotes is a literal quote. An unterminated quote throws Error at
// file:line:col.
std::vector<CsvField> split_csv_line(const std::string& line, char delim, const std::string& file,
                                     long line_no);

// Row by row over a text file (same rules as read_csv_rows), so that a reader can stop early
// and never tokenize the rest.
class CsvReader {
 public:
  CsvReader(const std::string& path, char delim, char comment = '#');
  // Over `text` held in memory (what a writer is about to write); `name` is the file named
  // in errors.
  static CsvReader from_text(std::string text, const std::string& name, char delim,
                             char comment = '#');
  bool next(CsvRow& row);  // false at the end of the file
  // Line ends left in the text: an upper bound of the rows next() still returns (a reader
  // reserves its output once instead of doubling it).
  size_t lines_left() const;

 private:
  struct FromText {};
  CsvReader(FromText, std::string text, const std::string& name, char delim, char comment);
  void skip_bom();
  std::string path_, text_;
  char delim_, comment_;
  size_t pos_ = 0;
  long line_no_ = 0;
};

// Reads a whole text file into rows. Blank lines are dropped; lines whose first non-space
// character is `comment` (if non-zero) are dropped. Handles \n, \r\n and lone \r line ends; a UTF-8
// BOM is skipped.
std::vector<CsvRow> read_csv_rows(const std::string& path, char delim, char comment = '#');

// `text` safe to quote in a one-line message: control characters (NUL, CR, ...) become
// \xNN, and text longer than `max_len` is cut with "...".
std::string printable(const std::string& text, size_t max_len = 60);

// Strict number parsing: the whole (trimmed) text must be a finite decimal number.
// Returns false and sets `why` ("empty field", "not a number: \"x\"", "non-finite value nan").
bool parse_number(const std::string& text, double& out, std::string& why);

}  // namespace fovsim
