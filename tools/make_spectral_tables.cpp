// Build-time generator of the spectral tables (include/gonio/spectrum/data_tables.h):
// the CIE 1931 2° colour-matching functions, D65 and the Schott glasses, read from the
// repository's data/ CSVs, and the RGB → spectrum coefficient table of Jakob & Hanika
// 2019 ("A Low-Dimensional Function Space for Efficient Spectral Upsampling", §4),
// computed here by gonio's own optimiser from those CIE tables.
//
// The fit. For every table node (rgb_table_layout.h) find c = (c0, c1, c2) such that the
// reflectance S(λ) = σ(c0 t² + c1 t + c2) (their eq. 3), lit by D65 and integrated against
// the CMFs (trapezoid rule on the 1 nm grid, cie.h's normalisation), has the CIELAB
// coordinates of the target rgb (linear sRGB → XYZ by the inverse of IEC 61966-2-1's
// matrix; white = XYZ of S = 1). Levenberg–Marquardt on the 3×3 residual with the
// analytic Jacobian (dσ/dx = 1 / (2 (1 + x²)^{3/2})), started from the solution at the
// neighbouring z node: nodes are visited from z ≈ 0.2 upwards and then downwards, for
// every (x, y), as the paper does, so that each fit starts close to its answer.
//
// Usage: gonio_make_spectral_tables DATA_DIR OUT.cpp

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "gonio/error.h"
#include "gonio/spectrum/color_space.h"
#include "gonio/spectrum/csv.h"
#include "gonio/spectrum/rgb_table_layout.h"

using namespace gonio;
namespace fs = std::filesystem;

namespace {

constexpr int kN = 471;  // 360..830 nm, 1 nm
using Vec = std::array<double, 3>;
using Mat = std::array<Vec, 3>;

struct Observer {
  std::vector<double> x, y, z;  // CMFs at 360 + k nm
  std::vector<double> d65;      // D65 at 360 + k nm (interpolated)
  std::vector<double> wx, wy, wz;  // trapezoid weight × D65 × CMF / ∫ ȳ D65
  double y_integral = 0, d65_scale = 0;
  int first = 0, last = kN - 1;  // the range where any weight is above 1e-9 of its maximum
  Vec white{};
};

// A quadrature: S sampled at normalised wavelengths t[i] with weights w*[i].
struct Quadrature {
  std::vector<double> t, wx, wy, wz;
};

// The fine rule: every 1 nm row of the tables (trapezoid rule), where the weights matter.
Quadrature fine_rule(const Observer& o) {
  Quadrature q;
  for (int k = o.first; k <= o.last; ++k) {
    q.t.push_back(k / 470.0);
    q.wx.push_back(o.wx[size_t(k)]), q.wy.push_back(o.wy[size_t(k)]), q.wz.push_back(o.wz[size_t(k)]);
  }
  return q;
}

// The coarse rule: S at every `step` nm, the fine weights distributed onto those nodes by
// the hat functions of linear interpolation; exact for an S that is piecewise linear
// between the nodes, and `step` times cheaper.
Quadrature coarse_rule(const Observer& o, int step) {
  Quadrature q;
  const int nodes = (kN - 1) / step + 1;
  q.t.resize(size_t(nodes)), q.wx.assign(size_t(nodes), 0), q.wy.assign(size_t(nodes), 0), q.wz.assign(size_t(nodes), 0);
  for (int m = 0; m < nodes; ++m) q.t[size_t(m)] = m * step / 470.0;
  for (int k = 0; k < kN; ++k) {
    const int m = std::min(k / step, nodes - 2);
    const double f = double(k - m * step) / step;
    q.wx[size_t(m)] += (1 - f) * o.wx[size_t(k)], q.wx[size_t(m) + 1] += f * o.wx[size_t(k)];
    q.wy[size_t(m)] += (1 - f) * o.wy[size_t(k)], q.wy[size_t(m) + 1] += f * o.wy[size_t(k)];
    q.wz[size_t(m)] += (1 - f) * o.wz[size_t(k)], q.wz[size_t(m) + 1] += f * o.wz[size_t(k)];
  }
  return q;
}

// CIELAB f and its derivative (CIE 15, §8.2.1).
constexpr double kDelta = 6.0 / 29.0;
double lab_f(double t) { return t > kDelta * kDelta * kDelta ? std::cbrt(t) : t / (3 * kDelta * kDelta) + 4.0 / 29.0; }
double lab_df(double t) {
  return t > kDelta * kDelta * kDelta ? 1.0 / (3 * std::cbrt(t) * std::cbrt(t)) : 1.0 / (3 * kDelta * kDelta);
}

Vec xyz_to_lab(const Vec& c, const Vec& w) {
  const double fx = lab_f(c[0] / w[0]), fy = lab_f(c[1] / w[1]), fz = lab_f(c[2] / w[2]);
  return {116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz)};
}

// Lab of the coefficients' reflectance and, with jac, dLab/dc.
void eval_lab(const Observer& o, const Quadrature& rule, const Vec& c, Vec& lab, Mat* jac) {
  Vec xyz{};
  Mat dxyz{};  // dxyz[i][j] = d XYZ_i / d c_j
  for (size_t k = 0; k < rule.t.size(); ++k) {
    const double t = rule.t[k];
    const double p = (c[0] * t + c[1]) * t + c[2];
    const double q = 1 / (1 + p * p);
    const double sq = std::sqrt(q);
    const double s = 0.5 + 0.5 * p * sq;
    const double w[3] = {rule.wx[k], rule.wy[k], rule.wz[k]};
    for (int i = 0; i < 3; ++i) xyz[size_t(i)] += s * w[i];
    if (jac) {
      const double ds = 0.5 * q * sq;
      const double dp[3] = {t * t, t, 1};
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) dxyz[size_t(i)][size_t(j)] += ds * dp[j] * w[i];
    }
  }
  lab = xyz_to_lab(xyz, o.white);
  if (!jac) return;
  const double gx = lab_df(xyz[0] / o.white[0]) / o.white[0];
  const double gy = lab_df(xyz[1] / o.white[1]) / o.white[1];
  const double gz = lab_df(xyz[2] / o.white[2]) / o.white[2];
  for (int j = 0; j < 3; ++j) {
    (*jac)[0][size_t(j)] = 116 * gy * dxyz[1][size_t(j)];
    (*jac)[1][size_t(j)] = 500 * (gx * dxyz[0][size_t(j)] - gy * dxyz[1][size_t(j)]);
    (*jac)[2][size_t(j)] = 200 * (gy * dxyz[1][size_t(j)] - gz * dxyz[2][size_t(j)]);
  }
}

// Squared CIELAB residual at which a fit stops: ΔE = 1e-3, far below visibility and
// ~1e-5 in linear sRGB.
constexpr double kTolerance = 1e-6;
// Largest |c_i| a fit may reach (t ∈ [0, 1]; c ~ 1e4 is already a spike a few nm wide).
constexpr double kMaxCoefficient = 1e5;

double norm2(const Vec& v) { return v[0] * v[0] + v[1] * v[1] + v[2] * v[2]; }

// Solves a 3×3 system by Cramer's rule; false when singular.
bool solve3(const Mat& a, const Vec& b, Vec& x) {
  const double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                     a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                     a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
  if (!std::isfinite(det) || std::abs(det) < 1e-300) return false;
  for (int col = 0; col < 3; ++col) {
    Mat m = a;
    for (int r = 0; r < 3; ++r) m[size_t(r)][size_t(col)] = b[size_t(r)];
    x[size_t(col)] = (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                      m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                      m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])) / det;
  }
  return true;
}

// Levenberg–Marquardt from c towards the Lab target; returns the final |residual|².
double fit(const Observer& o, const Quadrature& rule, const Vec& target_lab, Vec& c, int& iterations) {
  Vec lab;
  Mat j{};
  eval_lab(o, rule, c, lab, &j);
  Vec r{lab[0] - target_lab[0], lab[1] - target_lab[1], lab[2] - target_lab[2]};
  double err = norm2(r);
  iterations = 0;
  double mu = 1e-6;
  for (; iterations < 100 && err > kTolerance; ++iterations) {
    // (JᵀJ + μ diag(JᵀJ)) δ = Jᵀ r
    Mat a{};
    Vec g{};
    for (int p = 0; p < 3; ++p) {
      for (int q = 0; q < 3; ++q)
        for (int k = 0; k < 3; ++k) a[size_t(p)][size_t(q)] += j[size_t(k)][size_t(p)] * j[size_t(k)][size_t(q)];
      for (int k = 0; k < 3; ++k) g[size_t(p)] += j[size_t(k)][size_t(p)] * r[size_t(k)];
    }
    bool improved = false;
    for (int tries = 0; tries < 30 && !improved; ++tries) {
      Mat damped = a;
      for (int p = 0; p < 3; ++p) damped[size_t(p)][size_t(p)] *= 1 + mu;
      Vec delta;
      if (!solve3(damped, g, delta)) {
        mu = std::max(mu * 10, 1e-8);
        continue;
      }
      const Vec cn{c[0] - delta[0], c[1] - delta[1], c[2] - delta[2]};
      // Steps to absurd coefficients (a target no smooth spectrum reaches pulls them
      // towards infinity) are refused like steps that do not improve.
      if (!(std::abs(cn[0]) < kMaxCoefficient && std::abs(cn[1]) < kMaxCoefficient &&
            std::abs(cn[2]) < kMaxCoefficient)) {
        mu *= 10;
        continue;
      }
      Vec labn;
      eval_lab(o, rule, cn, labn, nullptr);
      const Vec rn{labn[0] - target_lab[0], labn[1] - target_lab[1], labn[2] - target_lab[2]};
      const double en = norm2(rn);
      if (std::isfinite(en) && en < err) {
        c = cn, r = rn, err = en;
        if (err > kTolerance) eval_lab(o, rule, c, labn, &j);
        mu = std::max(mu * 0.1, 1e-12);
        improved = true;
      } else {
        mu *= 10;
      }
    }
    if (!improved) break;
  }
  return err;
}

Observer load_observer(const fs::path& data) {
  Observer o;
  const auto cmf = read_csv_file((data / "cie" / "cie1931_2deg_cmf.csv").string(), 4);
  if (cmf.size() != size_t(kN)) throw InputError("CMF table: expected 471 rows (360..830 nm)");
  for (int k = 0; k < kN; ++k) {
    if (cmf[size_t(k)].values[0] != 360 + k) throw InputError("CMF table: row " + std::to_string(k) + " is not at 1 nm steps");
    o.x.push_back(cmf[size_t(k)].values[1]);
    o.y.push_back(cmf[size_t(k)].values[2]);
    o.z.push_back(cmf[size_t(k)].values[3]);
  }
  const auto d65 = read_csv_file((data / "cie" / "cie_illuminant_d65.csv").string(), 2);
  for (size_t i = 1; i < d65.size(); ++i)
    if (d65[i].values[0] - d65[i - 1].values[0] != 5) throw InputError("D65 table: not at 5 nm steps");
  const double first = d65.front().values[0];
  if (first > 360 || d65.back().values[0] < 830) throw InputError("D65 table: does not cover 360-830 nm");
  for (int k = 0; k < kN; ++k) {
    const double f = (360 + k - first) / 5;
    const size_t i = std::min(size_t(f), d65.size() - 2);
    const double t = f - double(i);
    o.d65.push_back(d65[i].values[1] + t * (d65[i + 1].values[1] - d65[i].values[1]));
  }
  double yd = 0;
  for (int k = 0; k < kN; ++k) {
    const double h = (k == 0 || k == kN - 1) ? 0.5 : 1.0;
    o.y_integral += h * o.y[size_t(k)];
    yd += h * o.y[size_t(k)] * o.d65[size_t(k)];
  }
  o.d65_scale = o.y_integral / yd;
  for (int k = 0; k < kN; ++k) {
    const double h = (k == 0 || k == kN - 1) ? 0.5 : 1.0;
    const double w = h * o.d65[size_t(k)] / yd;
    o.wx.push_back(w * o.x[size_t(k)]);
    o.wy.push_back(w * o.y[size_t(k)]);
    o.wz.push_back(w * o.z[size_t(k)]);
    o.white[0] += o.wx.back();
    o.white[1] += o.wy.back();
    o.white[2] += o.wz.back();
  }
  double wmax = 0;
  for (int k = 0; k < kN; ++k) wmax = std::max({wmax, o.wx[size_t(k)], o.wy[size_t(k)], o.wz[size_t(k)]});
  auto small = [&](int k) { return std::max({o.wx[size_t(k)], o.wy[size_t(k)], o.wz[size_t(k)]}) < 1e-9 * wmax; };
  while (o.first < o.last && small(o.first)) ++o.first;
  while (o.last > o.first && small(o.last)) --o.last;
  return o;
}

constexpr int R = rgb_table::kRes;
using Table = std::vector<float>;  // [z][y][x][3] for one l
size_t at(int zi, int yi, int xi) { return ((size_t(zi) * R + size_t(yi)) * R + size_t(xi)) * 3; }

struct FitStats {
  double worst_lab = 0;
  long iterations = 0;
};

void fit_table(const Observer& o, int l, Table& table, FitStats& stats) {
  const Quadrature coarse = coarse_rule(o, 5), fine = fine_rule(o);
  table.assign(size_t(R) * R * R * 3, 0.f);
  const int start = R / 5;
  for (int yi = 0; yi < R; ++yi) {
    for (int xi = 0; xi < R; ++xi) {
      const double x = double(xi) / (R - 1), y = double(yi) / (R - 1);
      auto solve_at = [&](int zi, Vec& c) {
        const double z = rgb_table::z_node(zi);
        Vec rgb{};
        rgb[size_t(l)] = z;
        rgb[size_t((l + 1) % 3)] = x * z;
        rgb[size_t((l + 2) % 3)] = y * z;
        const Vec target = xyz_to_lab(mat_mul(kLinearSrgbToXyz, rgb), o.white);
        // Most of the work on the 5 nm rule, then polished on the 1 nm one (the rule the
        // run-time conversion and the tests use): it starts within ~1e-3 of its answer.
        int it = 0, it_fine = 0;
        fit(o, coarse, target, c, it);
        const double err = fit(o, fine, target, c, it_fine);
        stats.iterations += it + it_fine;
        if (zi > 0) stats.worst_lab = std::max(stats.worst_lab, std::sqrt(err));
        for (int i = 0; i < 3; ++i) table[at(zi, yi, xi) + size_t(i)] = float(c[size_t(i)]);
      };
      // Start each fit from the linear extrapolation of the two previous nodes' solutions.
      auto coeffs = [&](int zi) {
        return Vec{table[at(zi, yi, xi)], table[at(zi, yi, xi) + 1], table[at(zi, yi, xi) + 2]};
      };
      auto predict = [&](int zi, int step) {
        const Vec a = coeffs(zi - step), b = coeffs(zi - 2 * step);
        const double f = (rgb_table::z_node(zi) - rgb_table::z_node(zi - step)) /
                         (rgb_table::z_node(zi - step) - rgb_table::z_node(zi - 2 * step));
        return Vec{a[0] + f * (a[0] - b[0]), a[1] + f * (a[1] - b[1]), a[2] + f * (a[2] - b[2])};
      };
      Vec c{0, 0, 0};
      for (int zi = start; zi < R; ++zi) {
        if (zi >= start + 2) c = predict(zi, 1);
        solve_at(zi, c);
      }
      for (int zi = start - 1; zi >= 1; --zi) {
        c = zi <= start - 2 ? predict(zi, -1) : coeffs(start);
        solve_at(zi, c);
      }
      // z = 0 is black, which no finite c reaches: keep the shape of the first node
      // (run time treats black exactly; colours below z_1 ≈ 3e-5 interpolate towards it).
      for (int i = 0; i < 3; ++i) table[at(0, yi, xi) + size_t(i)] = table[at(1, yi, xi) + size_t(i)];
    }
  }
}

void write_floats(FILE* out, const char* name, const std::vector<double>& v) {
  std::fprintf(out, "const float %s[] = {", name);
  for (size_t i = 0; i < v.size(); ++i) std::fprintf(out, "%s%.9g", i == 0 ? "\n  " : (i % 8 ? ", " : ",\n  "), v[i]);
  std::fprintf(out, "\n};\n");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s DATA_DIR OUT.cpp\n", argv[0]);
    return 2;
  }
  try {
    const fs::path data = argv[1];
    const Observer o = load_observer(data);

    std::vector<fs::path> glass_files;
    for (const auto& e : fs::directory_iterator(data / "glasses"))
      if (e.path().extension() == ".csv") glass_files.push_back(e.path());
    std::sort(glass_files.begin(), glass_files.end());

    Table tables[3];
    FitStats stats[3];
    {
      std::vector<std::thread> threads;
      for (int l = 0; l < 3; ++l) threads.emplace_back([&, l] { fit_table(o, l, tables[l], stats[l]); });
      for (auto& t : threads) t.join();
    }

    for (const auto& t : tables)
      for (const float v : t)
        if (!std::isfinite(v)) throw InputError("RGB -> spectrum fit produced a non-finite coefficient");

    FILE* out = std::fopen(argv[2], "w");
    if (!out) {
      std::perror(argv[2]);
      return 1;
    }
    std::fprintf(out, "// Generated by tools/make_spectral_tables.cpp from data/. Do not edit.\n");
    std::fprintf(out, "#include \"gonio/spectrum/data_tables.h\"\n\nnamespace gonio::spectral_data {\n\n");
    write_floats(out, "kCieX", o.x);
    write_floats(out, "kCieY", o.y);
    write_floats(out, "kCieZ", o.z);
    std::fprintf(out, "const double kCieYIntegral = %.17g;\n", o.y_integral);
    {
      // The spectral renderer's wavelength density (wavelengths.h, "sRGB-response density"):
      // per 1 nm bin, ‖(r̄, ḡ, b̄)‖^½ of the linear-sRGB colour-matching functions at the
      // bin's centre (the CIE 1931 CMFs, linearly interpolated, through IEC 61966-2-1's
      // matrix), normalised: its CDF at the bin edges, in double so that a bin's mass (the
      // difference of two values near 1) keeps its digits.
      std::vector<double> cdf(kN, 0.0);
      double sum = 0;
      for (int i = 0; i + 1 < kN; ++i) {
        const auto c = mat_mul(kXyzToLinearSrgb, {(o.x[size_t(i)] + o.x[size_t(i) + 1]) / 2,
                                                  (o.y[size_t(i)] + o.y[size_t(i) + 1]) / 2,
                                                  (o.z[size_t(i)] + o.z[size_t(i) + 1]) / 2});
        sum += std::sqrt(std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]));
        cdf[size_t(i) + 1] = sum;
      }
      if (!(sum > 0)) throw InputError("the colour-matching functions are zero everywhere");
      for (auto& v : cdf) v /= sum;
      cdf.back() = 1;
      std::fprintf(out, "const double kResponseCdf[] = {");
      for (size_t i = 0; i < cdf.size(); ++i)
        std::fprintf(out, "%s%.17g", i == 0 ? "\n  " : (i % 4 ? ", " : ",\n  "), cdf[i]);
      std::fprintf(out, "\n};\n");
      // A guide table (Chen & Asau 1974): for each of kResponseGuideSize equal intervals
      // of u, the bin holding the interval's start, from which a short forward scan finds
      // the bin of any u in it.
      const int guide_size = 1024;
      std::fprintf(out, "const unsigned short kResponseGuide[] = {");
      int bin = 0;
      for (int k = 0; k < guide_size; ++k) {
        const double start = double(k) / guide_size;
        while (bin < kN - 2 && cdf[size_t(bin) + 1] <= start) ++bin;
        std::fprintf(out, "%s%d", k == 0 ? "\n  " : (k % 16 ? ", " : ",\n  "), bin);
      }
      std::fprintf(out, "\n};\n");
    }
    const auto d65 = read_csv_file((data / "cie" / "cie_illuminant_d65.csv").string(), 2);
    std::vector<double> d65v;
    for (const auto& r : d65) d65v.push_back(r.values[1]);
    std::fprintf(out, "const int kD65FirstNm = %d;\nconst int kD65Samples = %zu;\n", int(d65.front().values[0]),
                 d65v.size());
    write_floats(out, "kD65", d65v);
    std::fprintf(out, "const double kD65Scale = %.17g;\n\n", o.d65_scale);

    std::string list;
    for (size_t g = 0; g < glass_files.size(); ++g) {
      const auto rows = read_csv_file(glass_files[g].string(), 2);
      std::vector<double> lam, n;
      for (const auto& r : rows) lam.push_back(r.values[0]), n.push_back(r.values[1]);
      write_floats(out, ("kGlassLambda" + std::to_string(g)).c_str(), lam);
      write_floats(out, ("kGlassN" + std::to_string(g)).c_str(), n);
      list += "  {\"" + glass_files[g].stem().string() + "\", kGlassLambda" + std::to_string(g) + ", kGlassN" +
              std::to_string(g) + ", " + std::to_string(rows.size()) + "},\n";
    }
    std::fprintf(out, "const int kGlassCount = %zu;\nconst GlassTable kGlasses[] = {\n%s};\n\n", glass_files.size(),
                 list.c_str());

    // The named metals' complex index n + i k (data/metals/<name>.csv: lambda_nm, n, k),
    // for spectral mode; RGB mode's constants come from tools/make_metal_table.cpp.
    std::vector<fs::path> metal_files;
    for (const auto& e : fs::directory_iterator(data / "metals"))
      if (e.path().extension() == ".csv") metal_files.push_back(e.path());
    std::sort(metal_files.begin(), metal_files.end());
    list.clear();
    for (size_t m = 0; m < metal_files.size(); ++m) {
      const auto rows = read_csv_file(metal_files[m].string(), 3);
      std::vector<double> lam, n, k;
      for (const auto& r : rows) lam.push_back(r.values[0]), n.push_back(r.values[1]), k.push_back(r.values[2]);
      const std::string i = std::to_string(m);
      write_floats(out, ("kMetalLambda" + i).c_str(), lam);
      write_floats(out, ("kMetalN" + i).c_str(), n);
      write_floats(out, ("kMetalK" + i).c_str(), k);
      list += "  {\"" + metal_files[m].stem().string() + "\", kMetalLambda" + i + ", kMetalN" + i + ", kMetalK" + i +
              ", " + std::to_string(rows.size()) + "},\n";
    }
    std::fprintf(out, "const int kMetalCount = %zu;\nconst MetalTable kMetals[] = {\n%s};\n\n", metal_files.size(),
                 list.c_str());

    std::fprintf(out, "const float kRgbCoefficients[3][%d][%d][%d][3] = {\n", R, R, R);
    for (int l = 0; l < 3; ++l) {
      std::fprintf(out, "{\n");
      for (int zi = 0; zi < R; ++zi) {
        std::fprintf(out, " {\n");
        for (int yi = 0; yi < R; ++yi) {
          std::fprintf(out, "  {");
          for (int xi = 0; xi < R; ++xi) {
            const float* c = &tables[l][at(zi, yi, xi)];
            std::fprintf(out, "{%.9g,%.9g,%.9g},", double(c[0]), double(c[1]), double(c[2]));
          }
          std::fprintf(out, "},\n");
        }
        std::fprintf(out, " },\n");
      }
      std::fprintf(out, "},\n");
    }
    std::fprintf(out, "};\n\n}  // namespace gonio::spectral_data\n");
    if (std::fclose(out) != 0) {
      std::perror(argv[2]);
      return 1;
    }
    double worst = 0;
    long its = 0;
    for (const auto& s : stats) worst = std::max(worst, s.worst_lab), its += s.iterations;
    std::printf("RGB -> spectrum table %d^3 x 3: worst CIELAB residual at the nodes %.3g, %ld LM iterations\n", R,
                worst, its);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gonio_make_spectral_tables: %s\n", e.what());
    return 2;
  }
  return 0;
}
