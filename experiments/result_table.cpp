#include "experiments/result_table.h"

#include <cmath>
#include <iomanip>
#include <sstream>

#include "solvers/error.h"

namespace bivo::experiments {

ResultTable::ResultTable(std::string corner_, std::vector<std::string> rows_, std::vector<std::string> columns_)
    : corner(std::move(corner_)), rows(std::move(rows_)), columns(std::move(columns_)) {
  values.assign(rows.size(), std::vector<std::optional<double>>(columns.size()));
  texts.assign(rows.size(), std::vector<std::string>(columns.size()));
}

void ResultTable::set(int row, int column, double value) {
  if (!std::isfinite(value)) {
    throw Error("result table: non-finite value for '" + rows.at(row) + "' / '" + columns.at(column) + "'");
  }
  values.at(row).at(column) = value;
}

void ResultTable::set_text(int row, int column, std::string text) { texts.at(row).at(column) = std::move(text); }

int ResultTable::best_row(int column) const {
  int best = -1;
  for (int r = 0; r < int(rows.size()); ++r) {
    const auto& v = values[r][column];
    if (v && (best < 0 || *v < *values[best][column])) best = r;
  }
  return best;
}

std::string ResultTable::markdown() const {
  std::ostringstream s;
  s << "| " << corner << " |";
  for (const auto& c : columns) s << " " << c << " |";
  s << "\n|---|";
  for (size_t c = 0; c < columns.size(); ++c) s << "---:|";
  s << "\n";
  for (int r = 0; r < int(rows.size()); ++r) {
    s << "| " << rows[r] << " |";
    for (int c = 0; c < int(columns.size()); ++c) {
      const auto& v = values[r][c];
      if (!v) {
        s << " " << (texts[r][c].empty() ? "—" : texts[r][c]) << " |";
        continue;
      }
      std::ostringstream num;
      num << std::fixed << std::setprecision(precision) << *v;
      const bool bold = mark_best && best_row(c) == r && rows.size() > 1;
      s << " " << (bold ? "**" + num.str() + "**" : num.str()) << " |";
    }
    s << "\n";
  }
  return s.str();
}

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string out = "\"";
  for (char ch : text) {
    if (ch == '"') out += '"';
    out += ch;
  }
  return out + "\"";
}

std::string ResultTable::csv() const {
  std::ostringstream s;
  s << csv_field(corner);
  for (const auto& c : columns) s << "," << csv_field(c);
  s << "\n";
  for (int r = 0; r < int(rows.size()); ++r) {
    s << csv_field(rows[r]);
    for (int c = 0; c < int(columns.size()); ++c) {
      s << ",";
      if (values[r][c]) s << std::setprecision(10) << *values[r][c];
    }
    s << "\n";
  }
  return s.str();
}

}  // namespace bivo::experiments
