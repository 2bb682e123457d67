// Build-time generator of the named metals' RGB constants (src/metals.cpp) from the
// measured spectra in data/metals/<name>.csv, so that the numbers gonio uses are the data,
// not a transcription of it. It includes none of gonio's headers: it runs before the
// library exists, and reads the CIE tables itself.
//
// Reduction to RGB (issue 11, item 4): RGB mode's normal-incidence reflectance of each
// channel equals the colour of the metal's measured reflectance spectrum. Per metal:
//   1. R(λ) = F0(n(λ), k(λ)) = ((n−1)² + k²) / ((n+1)² + k²)  (normal incidence, Born &
//      Wolf §14.2 eq. 21 at θ = 0), with n(λ), k(λ) piecewise-linear between the rows of
//      the table (SPEC §2's rule for named metals);
//   2. (R_r, R_g, R_b) = linear sRGB of R under D65, the reduction gonio applies to a
//      {"spectrum": ...} reflectance (spectrum_to_rgb.h):
//        XYZ = Σ_i w_i R(λ_i) D65(λ_i) x̄ȳz̄(λ_i) / Σ_i w_i D65(λ_i) ȳ(λ_i)   (CIE 15:2004
//      §7.1), the trapezoid rule on the rows of the CIE 1931 2° table (1 nm, 360–830 nm),
//      D65 interpolated linearly between its rows; RGB = M · XYZ with M the XYZ → linear
//      sRGB matrix of IEC 61966-2-1:1999 eq. 5.2 (D65 white); each channel clamped to
//      [0, 1], then capped at kMaxReflectance = 0.999: F0 = 1 needs k = ∞, and gold's red
//      channel is out of the sRGB gamut (1.022 before the clamp), so it gets F0 = 0.999
//      (k ≈ 26 at n = 0.168) — 0.1 % under the clamped colour;
//   3. the channel's n is the point sample n(λ_c) at λ_c = 650 nm (r), 550 nm (g),
//      450 nm (b), and k solves F0(n, k) = R_c:
//        k = sqrt(((n+1)² R − (n−1)²) / (1 − R));
//      if the radicand is negative (n alone already reflects more than R), k = 0 and n
//      solves ((n−1)/(n+1))² = R on the same side of 1 as the sample:
//        n = (1 + √R)/(1 − √R) if n(λ_c) ≥ 1, else (1 − √R)/(1 + √R).
// At other angles the RGB Fresnel curve is that of this (n, k), not an average of the
// spectral curves; only normal incidence is matched.
//
// CSV format: lines starting with '#' are comments (a metal's first ones name the source
// and are copied into the output), one header line, then rows of numbers with strictly
// increasing wavelengths in the first column. Headers: "lambda_nm,n,k" (metals),
// "lambda_nm,x_bar,y_bar,z_bar" (observer), "lambda_nm,power" (D65).
//
// Usage: gonio_make_metal_table OUT.cpp CMF.csv D65.csv NAME=FILE.csv [NAME=FILE.csv ...]
// Every error is one line on stderr, naming the file and line, and exit status 1.

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

struct Table {
  std::string path;
  std::vector<std::string> comments;       // before the header
  std::vector<std::vector<double>> rows;   // first column: wavelength in nm
  std::vector<int> lines;                  // each row's line number in the file
};

struct Metal {
  std::string name;
  Table table;
};

constexpr double kChannelNm[3] = {650, 550, 450};
// The largest channel reflectance given an index (step 2 of the header).
constexpr double kMaxReflectance = 0.999;

// IEC 61966-2-1:1999 eq. 5.2: XYZ (D65 white) → linear sRGB.
constexpr double kXyzToSrgb[3][3] = {
    {3.2406, -1.5372, -0.4986},
    {-0.9689, 1.8758, 0.0415},
    {0.0557, -0.2040, 1.0570},
};

[[noreturn]] void fail(const std::string& message) { throw std::runtime_error(message); }

double parse_number(const std::string& field, const std::string& where) {
  const char* begin = field.c_str();
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(begin, &end);
  while (*end == ' ' || *end == '\t' || *end == '\r') ++end;
  if (end == begin || *end != '\0' || errno == ERANGE || !std::isfinite(v))
    fail(where + ": '" + field + "' is not a number");
  return v;
}

Table read_table(const std::string& path, const std::string& header) {
  std::ifstream in(path);
  if (!in) fail(path + ": cannot open");
  const size_t columns = size_t(std::count(header.begin(), header.end(), ',')) + 1;
  Table t{path, {}, {}, {}};
  std::string line;
  bool header_seen = false;
  for (int number = 1; std::getline(in, line); ++number) {
    const std::string where = path + ":" + std::to_string(number);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    if (line[0] == '#') {
      if (!header_seen) t.comments.push_back(line.substr(1));
      continue;
    }
    if (!header_seen) {
      if (line != header) fail(where + ": expected the header '" + header + "'");
      header_seen = true;
      continue;
    }
    std::vector<std::string> fields;
    size_t start = 0;
    for (size_t comma; (comma = line.find(',', start)) != std::string::npos; start = comma + 1)
      fields.push_back(line.substr(start, comma - start));
    fields.push_back(line.substr(start));
    if (fields.size() != columns)
      fail(where + ": expected " + std::to_string(columns) + " comma-separated numbers, got " +
           std::to_string(fields.size()));
    std::vector<double> row;
    for (const auto& f : fields) row.push_back(parse_number(f, where));
    if (!t.rows.empty() && !(row[0] > t.rows.back()[0])) fail(where + ": wavelengths must increase strictly");
    t.rows.push_back(std::move(row));
    t.lines.push_back(number);
  }
  if (!header_seen || t.rows.size() < 2) fail(path + ": no table (need the header and at least 2 rows)");
  return t;
}

// Column `col` at lambda, piecewise-linear between the rows that bracket it (SPEC §2);
// nothing outside the table.
bool interpolate(const Table& t, double lambda, size_t col, double& out) {
  const auto& r = t.rows;
  if (!(lambda >= r.front()[0] && lambda <= r.back()[0])) return false;
  size_t i = size_t(std::upper_bound(r.begin(), r.end(), lambda,
                                     [](double l, const std::vector<double>& row) { return l < row[0]; }) -
                    r.begin());
  i = std::clamp<size_t>(i, 1, r.size() - 1);
  const auto& a = r[i - 1];
  const auto& b = r[i];
  const double s = (lambda - a[0]) / (b[0] - a[0]);
  out = a[col] + s * (b[col] - a[col]);
  return true;
}

double metal_value(const Metal& m, double lambda, size_t col) {
  double v = 0;
  if (!interpolate(m.table, lambda, col, v)) {
    char nm[32];
    std::snprintf(nm, sizeof nm, "%g", lambda);
    fail(m.table.path + ": the table does not cover " + nm + " nm");
  }
  return v;
}

// Normal-incidence reflectance of n + ik from vacuum (Born & Wolf §14.2, eq. 21 at θ = 0).
double f0(double n, double k) { return ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k); }

// The colour of the metal's reflectance spectrum (step 2 of the header), clamped and capped.
void reflectance_rgb(const Metal& m, const Table& cmf, const Table& d65, double rgb[3]) {
  double xyz[3] = {0, 0, 0}, white_y = 0;
  const auto& c = cmf.rows;
  for (size_t i = 0; i < c.size(); ++i) {
    // Trapezoid weights on the observer's own rows.
    const double lo = i > 0 ? c[i][0] - c[i - 1][0] : 0;
    const double hi = i + 1 < c.size() ? c[i + 1][0] - c[i][0] : 0;
    const double w = (lo + hi) / 2;
    const double lambda = c[i][0];
    double e = 0;
    if (!interpolate(d65, lambda, 1, e)) e = 0;  // 0 outside its table, as gonio's d65()
    const double r = f0(metal_value(m, lambda, 1), metal_value(m, lambda, 2));
    for (int j = 0; j < 3; ++j) xyz[j] += w * r * e * c[i][1 + size_t(j)];
    white_y += w * e * c[i][2];
  }
  if (!(white_y > 0)) fail(d65.path + ": D65 does not overlap the observer's range");
  for (int j = 0; j < 3; ++j) {
    double v = 0;
    for (int l = 0; l < 3; ++l) v += kXyzToSrgb[j][l] * xyz[l] / white_y;
    rgb[j] = std::min(std::clamp(v, 0.0, 1.0), kMaxReflectance);
  }
}

// Step 3 of the header: (n, k) with F0(n, k) = R, n kept at the sample if possible.
void solve_index(double n_sample, double R, double& n, double& k) {
  const double radicand = ((n_sample + 1) * (n_sample + 1) * R - (n_sample - 1) * (n_sample - 1)) / (1 - R);
  if (radicand >= 0) {
    n = n_sample;
    k = std::sqrt(radicand);
  } else {
    const double s = std::sqrt(R);
    n = n_sample >= 1 ? (1 + s) / (1 - s) : (1 - s) / (1 + s);
    k = 0;
  }
}

void write_table(const std::string& out_path, const std::vector<Metal>& metals, const Table& cmf,
                 const Table& d65) {
  std::string text =
      "// Generated at build time by tools/make_metal_table.cpp from data/metals/*.csv and\n"
      "// data/cie/*.csv. Each channel's n is the measured n at 650 nm (r), 550 nm (g),\n"
      "// 450 nm (b); k is chosen so that the channel's normal-incidence reflectance equals\n"
      "// the linear-sRGB colour (D65) of the measured reflectance spectrum (see the tool's\n"
      "// header). Do not edit.\n\n"
      "#include \"metals_table.h\"\n\n"
      "namespace gonio::detail {\n\n"
      "namespace {\n"
      "constexpr MetalEntry kMetals[] = {\n";
  char buf[512];
  for (const Metal& m : metals) {
    for (const auto& c : m.table.comments) text += "    //" + c + "\n";
    double rgb[3], n[3], k[3];
    reflectance_rgb(m, cmf, d65, rgb);
    for (int c = 0; c < 3; ++c) solve_index(metal_value(m, kChannelNm[c], 1), rgb[c], n[c], k[c]);
    std::snprintf(buf, sizeof buf, "    // Normal-incidence reflectance, linear sRGB of the spectrum, capped: %.6f %.6f %.6f\n",
                  rgb[0], rgb[1], rgb[2]);
    text += buf;
    std::snprintf(buf, sizeof buf, "    {\"%s\", {%.9gf, %.9gf, %.9gf}, {%.9gf, %.9gf, %.9gf}},\n", m.name.c_str(), n[0],
                  n[1], n[2], k[0], k[1], k[2]);
    text += buf;
  }
  text +=
      "};\n"
      "}  // namespace\n\n"
      "std::span<const MetalEntry> metal_table() { return kMetals; }\n\n"
      "}  // namespace gonio::detail\n";
  FILE* out = std::fopen(out_path.c_str(), "w");
  if (!out) fail(out_path + ": cannot write");
  const bool ok = std::fwrite(text.data(), 1, text.size(), out) == text.size();
  if (std::fclose(out) != 0 || !ok) fail(out_path + ": cannot write");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr, "usage: %s OUT.cpp CMF.csv D65.csv NAME=FILE.csv [NAME=FILE.csv ...]\n", argv[0]);
    return 1;
  }
  try {
    const Table cmf = read_table(argv[2], "lambda_nm,x_bar,y_bar,z_bar");
    const Table d65 = read_table(argv[3], "lambda_nm,power");
    for (const Table* t : {&cmf, &d65})
      for (size_t r = 0; r < t->rows.size(); ++r)
        for (size_t c = 1; c < t->rows[r].size(); ++c)
          if (!(t->rows[r][c] >= 0)) fail(t->path + ":" + std::to_string(t->lines[r]) + ": values must be >= 0");
    std::vector<Metal> metals;
    for (int i = 4; i < argc; ++i) {
      const std::string arg = argv[i];
      const size_t eq = arg.find('=');
      if (eq == 0 || eq == std::string::npos) fail("argument '" + arg + "' is not NAME=FILE.csv");
      Metal m{arg.substr(0, eq), read_table(arg.substr(eq + 1), "lambda_nm,n,k")};
      for (size_t r = 0; r < m.table.rows.size(); ++r)
        if (!(m.table.rows[r][1] > 0) || !(m.table.rows[r][2] >= 0))
          fail(m.table.path + ":" + std::to_string(m.table.lines[r]) + ": n must be > 0 and k >= 0");
      if (m.table.rows.front()[0] > cmf.rows.front()[0] || m.table.rows.back()[0] < cmf.rows.back()[0]) {
        char range[128];
        std::snprintf(range, sizeof range, ": the table covers %g-%g nm, not the observer's %g-%g nm",
                      m.table.rows.front()[0], m.table.rows.back()[0], cmf.rows.front()[0], cmf.rows.back()[0]);
        fail(m.table.path + range);
      }
      metals.push_back(std::move(m));
    }
    write_table(argv[1], metals, cmf, d65);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gonio_make_metal_table: %s\n", e.what());
    std::remove(argv[1]);
    return 1;
  }
  return 0;
}
