// Build-time generator of the named metals' RGB constants (src/metals.cpp) from the
// measured spectra in data/metals/<name>.csv, so that the numbers gonio uses are the data,
// not a transcription of it.
//
// Reduction to RGB: each channel takes the complex index at one wavelength, r = 650 nm,
// g = 550 nm, b = 450 nm, linearly interpolated between the two neighbouring rows of the
// table (the rule SPEC §2 gives for named metals: piecewise-linear between rows). It is a
// point sample, not an average over the sRGB primaries' responses: the 0.1 constants were
// defined this way, and tests/reference/models_reference.py derives them independently by
// the same rule.
//
// CSV format: lines starting with '#' are comments (the first ones name the source and are
// copied into the output), one header line "lambda_nm,n,k", then rows of three numbers
// with strictly increasing wavelengths.
//
// Usage: gonio_make_metal_table OUT.cpp NAME=FILE.csv [NAME=FILE.csv ...]
// Every error is one line on stderr, naming the file and line, and exit status 1.

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

struct Row {
  double lambda, n, k;
};

struct Metal {
  std::string name, path;
  std::vector<std::string> comments;
  std::vector<Row> rows;
};

constexpr double kChannelNm[3] = {650, 550, 450};

[[noreturn]] void fail(const std::string& message) { throw std::runtime_error(message); }

double parse_number(const std::string& field, const std::string& where) {
  const char* begin = field.c_str();
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(begin, &end);
  while (*end == ' ' || *end == '\t' || *end == '\r') ++end;
  if (end == begin || *end != '\0' || errno == ERANGE)
    fail(where + ": '" + field + "' is not a number");
  return v;
}

Metal read_metal(const std::string& name, const std::string& path) {
  std::ifstream in(path);
  if (!in) fail(path + ": cannot open");
  Metal m{name, path, {}, {}};
  std::string line;
  bool header_seen = false;
  for (int number = 1; std::getline(in, line); ++number) {
    const std::string where = path + ":" + std::to_string(number);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    if (line[0] == '#') {
      if (!header_seen) m.comments.push_back(line.substr(1));
      continue;
    }
    if (!header_seen) {
      if (line != "lambda_nm,n,k") fail(where + ": expected the header 'lambda_nm,n,k'");
      header_seen = true;
      continue;
    }
    std::vector<std::string> fields;
    size_t start = 0;
    for (size_t comma; (comma = line.find(',', start)) != std::string::npos; start = comma + 1)
      fields.push_back(line.substr(start, comma - start));
    fields.push_back(line.substr(start));
    if (fields.size() != 3) fail(where + ": expected 3 comma-separated numbers, got " + std::to_string(fields.size()));
    const Row r{parse_number(fields[0], where), parse_number(fields[1], where), parse_number(fields[2], where)};
    if (!m.rows.empty() && !(r.lambda > m.rows.back().lambda))
      fail(where + ": wavelengths must increase strictly");
    if (!(r.n > 0) || !(r.k >= 0)) fail(where + ": n must be > 0 and k >= 0");
    m.rows.push_back(r);
  }
  if (!header_seen || m.rows.size() < 2) fail(path + ": no table (need the header and at least 2 rows)");
  return m;
}

// Piecewise-linear between the rows that bracket lambda (SPEC §2).
Row interpolate(const Metal& m, double lambda) {
  for (size_t i = 0; i + 1 < m.rows.size(); ++i) {
    const Row& a = m.rows[i];
    const Row& b = m.rows[i + 1];
    if (a.lambda <= lambda && lambda <= b.lambda) {
      const double t = (lambda - a.lambda) / (b.lambda - a.lambda);
      return {lambda, a.n + t * (b.n - a.n), a.k + t * (b.k - a.k)};
    }
  }
  fail(m.path + ": the table does not cover " + std::to_string(int(lambda)) + " nm");
}

void write_table(const std::string& out_path, const std::vector<Metal>& metals) {
  FILE* out = std::fopen(out_path.c_str(), "w");
  if (!out) fail(out_path + ": cannot write");
  std::fprintf(out,
               "// Generated at build time by tools/make_metal_table.cpp from data/metals/*.csv.\n"
               "// Each channel is the complex index at 650 nm (r), 550 nm (g), 450 nm (b),\n"
               "// linearly interpolated between the table's rows. Do not edit.\n\n"
               "#include \"metals_table.h\"\n\n"
               "namespace gonio::detail {\n\n"
               "namespace {\n"
               "constexpr MetalEntry kMetals[] = {\n");
  for (const Metal& m : metals) {
    for (const auto& c : m.comments) std::fprintf(out, "    //%s\n", c.c_str());
    Row ch[3];
    for (int c = 0; c < 3; ++c) ch[c] = interpolate(m, kChannelNm[c]);
    std::fprintf(out, "    {\"%s\", {%.9gf, %.9gf, %.9gf}, {%.9gf, %.9gf, %.9gf}},\n", m.name.c_str(),
                 ch[0].n, ch[1].n, ch[2].n, ch[0].k, ch[1].k, ch[2].k);
  }
  std::fprintf(out,
               "};\n"
               "}  // namespace\n\n"
               "std::span<const MetalEntry> metal_table() { return kMetals; }\n\n"
               "}  // namespace gonio::detail\n");
  if (std::fclose(out) != 0) fail(out_path + ": cannot write");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s OUT.cpp NAME=FILE.csv [NAME=FILE.csv ...]\n", argv[0]);
    return 1;
  }
  try {
    std::vector<Metal> metals;
    for (int i = 2; i < argc; ++i) {
      const std::string arg = argv[i];
      const size_t eq = arg.find('=');
      if (eq == 0 || eq == std::string::npos) fail("argument '" + arg + "' is not NAME=FILE.csv");
      metals.push_back(read_metal(arg.substr(0, eq), arg.substr(eq + 1)));
    }
    write_table(argv[1], metals);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gonio_make_metal_table: %s\n", e.what());
    std::remove(argv[1]);
    return 1;
  }
  return 0;
}
