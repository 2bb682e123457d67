#include "gonio/spectrum/csv.h"

#include <charconv>
#include <cmath>
#include <optional>

#include "gonio/error.h"
#include "gonio/json_text.h"

namespace gonio {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> fields;
  if (line.find(',') != std::string_view::npos) {
    size_t start = 0;
    while (true) {
      const size_t comma = line.find(',', start);
      fields.push_back(trim(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
      if (comma == std::string_view::npos) break;
      start = comma + 1;
    }
  } else {
    size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
      const size_t start = i;
      while (i < line.size() && !(line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
      if (i > start) fields.push_back(line.substr(start, i - start));
    }
  }
  return fields;
}

// A finite number taking the whole field (no hex, no inf/nan).
std::optional<double> parse_number(std::string_view f) {
  if (f.empty()) return std::nullopt;
  if (f.front() == '+') f.remove_prefix(1);
  double v = 0;
  const auto [ptr, ec] = std::from_chars(f.data(), f.data() + f.size(), v, std::chars_format::general);
  if (ec != std::errc() || ptr != f.data() + f.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

}  // namespace

std::vector<CsvRow> parse_csv(std::string_view text, std::string_view source, int columns) {
  const std::string where(source);
  std::vector<CsvRow> rows;
  bool header_allowed = true;
  int line_no = 0;
  size_t pos = 0;
  while (pos <= text.size()) {
    const size_t nl = text.find('\n', pos);
    std::string_view line = text.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos);
    pos = nl == std::string_view::npos ? text.size() + 1 : nl + 1;
    ++line_no;
    if (const size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    line = trim(line);
    if (line.empty()) continue;
    const auto fields = split_fields(line);
    const std::string at = where + ":" + std::to_string(line_no) + ": ";
    std::vector<double> values;
    bool any_number = false;
    std::string_view bad;
    for (const auto f : fields) {
      const auto v = parse_number(f);
      if (v) {
        values.push_back(*v);
        any_number = true;
      } else if (bad.data() == nullptr) {
        bad = f;
      }
    }
    if (header_allowed && !any_number && int(fields.size()) == columns) {  // e.g. lambda_nm,value
      header_allowed = false;
      continue;
    }
    header_allowed = false;
    if (int(fields.size()) != columns)
      throw InputError(at + "expected " + std::to_string(columns) + " columns, got " +
                       std::to_string(fields.size()) + " ('" + std::string(line.substr(0, 60)) + "')");
    if (bad.data() != nullptr)
      throw InputError(at + "'" + std::string(bad.substr(0, 40)) + "' is not a finite number");
    rows.push_back({line_no, std::move(values)});
  }
  if (rows.empty()) throw InputError(where + ": no data rows");
  return rows;
}

std::vector<CsvRow> read_csv_file(const std::string& path, int columns) {
  return parse_csv(read_text_file(path, kMaxSpectrumFileBytes, "a spectrum file"), path, columns);
}

}  // namespace gonio
