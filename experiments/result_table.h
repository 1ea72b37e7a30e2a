#pragma once
// A rows x columns table of numbers (methods x sequences) rendered as Markdown, with the
// best entry of every column in bold (paper tables 1-3), and as CSV. Missing entries
// (a run that failed or was not made) print as "—" / empty, never as a number.
#include <optional>
#include <string>
#include <vector>

namespace bivo::experiments {

struct ResultTable {
  std::string corner;  // header of the row-label column, e.g. "method"
  std::vector<std::string> rows, columns;
  std::vector<std::vector<std::optional<double>>> values;  // [row][column]
  bool mark_best = true;                                   // bold the minimum of each column
  int precision = 6;                                       // digits after the point

  ResultTable(std::string corner, std::vector<std::string> rows, std::vector<std::string> columns);
  std::vector<std::vector<std::string>> texts;           // shown instead of "—" where no value
  void set(int row, int column, double value);           // throws bivo::Error on a non-finite value
  void set_text(int row, int column, std::string text);  // Markdown only; the CSV cell stays empty
  // Index of the smallest value of the column, -1 when the column is empty.
  int best_row(int column) const;
  std::string markdown() const;
  std::string csv() const;  // "corner,col1,col2\nrow,1.0,\n" (RFC 4180 quoting where needed)
};

// Quotes a CSV field when it contains a comma, quote or newline.
std::string csv_field(const std::string& text);

}  // namespace bivo::experiments
