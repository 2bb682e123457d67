#pragma once
// Numeric CSV tables: the data files of data/ and user spectra ({"spectrum": "file.csv"},
// SPEC §2). One row a line, fields separated by commas (or, with no comma on the line, by
// blanks); `#` starts a comment that runs to the end of the line; blank lines are
// skipped; the first data line may be a header whose fields are all non-numeric
// (`lambda_nm,value`). Errors are InputErrors that name file:line.

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace gonio {

struct CsvRow {
  int line;                    // 1-based line number in the file
  std::vector<double> values;  // exactly the requested number of columns, all finite
};

// Largest spectrum file read (a 1 nm table of the visible range is 10 KB).
inline constexpr std::size_t kMaxSpectrumFileBytes = std::size_t(4) << 20;  // 4 MiB

// Parses `text`; `source` names it in messages ("file.csv:7: ..."). Every data row must
// hold exactly `columns` finite numbers; at least one row is required.
std::vector<CsvRow> parse_csv(std::string_view text, std::string_view source, int columns);

// The file at `path` (bounded read), parsed as above.
std::vector<CsvRow> read_csv_file(const std::string& path, int columns);

}  // namespace gonio
