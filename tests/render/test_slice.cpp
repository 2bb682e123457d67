// The θh × θd slice figure (render/slice.h): pixels against f computed here from closed
// forms, the horizon from the geometry of the half/difference angles, the difference
// panel, the colour maps and the font. Small panels keep it cheap (about 0.1 s).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>
#include <string>

#include "../test_common.h"
#include "gonio/material.h"
#include "gonio/render/bitmap_font.h"
#include "gonio/render/colormap.h"
#include "gonio/render/slice.h"

namespace gonio::render {
namespace {

constexpr int kSize = 64;  // panel side for these tests

double luma(double r, double g, double b) { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }

// sRGB code value of a linear pixel, per channel (what the PNG holds).
std::array<double, 3> codes(const Color& c) { return {srgb_encode(c[0]), srgb_encode(c[1]), srgb_encode(c[2])}; }

double code_distance(const Color& a, const Color& b) {
  const auto x = codes(a), y = codes(b);
  return std::max({std::abs(x[0] - y[0]), std::abs(x[1] - y[1]), std::abs(x[2] - y[2])});
}

// The pixel of panel p whose centre is nearest (θh, θd) in degrees, on a linear θh axis:
// θh from 0 at the left edge to 90 at the right, θd from 0 at the bottom to 90 at the top.
const Color& pixel_at(const SliceFigure& fig, int panel, double theta_h, double theta_d) {
  const Rect& p = fig.panels[size_t(panel)];
  const int px = std::clamp(int(theta_h / 90 * p.width), 0, p.width - 1);
  const int py = std::clamp(int((1 - theta_d / 90) * p.height), 0, p.height - 1);
  return fig.image.at(p.x + px, p.y + py);
}
// Centre angles of that pixel.
double centre_theta_h(double theta_h) { return (std::clamp(int(theta_h / 90 * kSize), 0, kSize - 1) + 0.5) / kSize * 90; }
double centre_theta_d(double theta_d) {
  return (1 - (std::clamp(int((1 - theta_d / 90) * kSize), 0, kSize - 1) + 0.5) / kSize) * 90;
}

// The colour of the log bar where it shows value y (the row whose centre is nearest).
const Color& bar_colour_of_value(const SliceFigure& fig, double y) {
  const double t = (std::log10(y) - std::log10(fig.lo)) / (std::log10(fig.hi) - std::log10(fig.lo));
  const Rect& b = fig.bar;
  const int row = std::clamp(int(std::lround((1 - t) * b.height - 0.5)), 0, b.height - 1);
  return fig.image.at(b.x + b.width / 2, b.y + row);
}
// The colour of the difference bar at relative difference d.
const Color& bar_colour_of_difference(const SliceFigure& fig, double d) {
  const double t = d / fig.diff_range;  // in [−1, 1], top = +1
  const Rect& b = *fig.diff_bar;
  const int row = std::clamp(int(std::lround((1 - t) / 2 * b.height - 0.5)), 0, b.height - 1);
  return fig.image.at(b.x + b.width / 2, b.y + row);
}

bool is_horizon(const Color& c) {
  return code_distance(c, from_srgb(kSliceHorizon[0], kSliceHorizon[1], kSliceHorizon[2])) < 1e-6;
}

// One bar row spans 1/64 of the scale: neighbouring rows differ by up to ~0.02 in code.
constexpr double kBarTolerance = 0.02;

TEST(Slice, DiffuseIsOneColourThatOfItsValueOnTheBar) {
  // f = ρ/π (Lambert): every pixel above the horizon shows Y(ρ)/π.
  const BxDF diffuse = parse_material(R"({"type":"diffuse","reflectance":[0.2,0.5,0.8]})");
  SliceOptions o;
  o.size = kSize;
  const SliceFigure fig = make_slice(diffuse, nullptr, o);
  ASSERT_EQ(fig.panels.size(), 1u);
  EXPECT_FALSE(fig.diff_bar);
  const double y = luma(0.2, 0.5, 0.8) / kPiD;  // 0.1457
  EXPECT_DOUBLE_EQ(fig.lo, 0.1);                // whole decades around it
  EXPECT_DOUBLE_EQ(fig.hi, 1.0);
  const Rect& p = fig.panels[0];
  const Color first = fig.image.at(p.x, p.y);
  for (int py = 0; py < p.height; ++py)
    for (int px = 0; px < p.width; ++px) ASSERT_EQ(fig.image.at(p.x + px, p.y + py), first) << px << " " << py;
  EXPECT_LT(code_distance(first, bar_colour_of_value(fig, y)), kBarTolerance);
  // And not that of a value 10% off (the luminance weights matter).
  EXPECT_GT(code_distance(first, bar_colour_of_value(fig, 1.1 * y)), 2 * kBarTolerance);
}

// GGX with Schlick's Fresnel from the papers: D (Walter et al. 2007, eq. 33), the
// height-correlated Smith G2 = 1 / (1 + Λ(wo) + Λ(wi)) with Λ = (−1 + √(1 + α² tan² θ)) / 2
// (Heitz 2014, eqs. 72, 99), F = F0 + (1 − F0)(1 − cos θd)^5 (Schlick 1994), and
// f = F D G2 / (4 cos θi cos θo) (Walter et al. 2007, eq. 20). At φd = 90° and φh = 0 the
// directions are wi, wo = (cos θd sin θh, ±sin θd, cos θd cos θh): both at cos θ =
// cos θd cos θh, with the half vector at θh and cos(wi, h) = cos θd.
double ggx_schlick_luminance(double alpha, const double (&f0)[3], double theta_h, double theta_d) {
  const double a2 = alpha * alpha;
  const double ch = std::cos(theta_h), t2h = std::pow(std::tan(theta_h), 2);
  const double d = a2 / (kPiD * std::pow(ch, 4) * std::pow(a2 + t2h, 2));
  const double cos_io = std::cos(theta_d) * ch;
  const double tan2 = (1 - cos_io * cos_io) / (cos_io * cos_io);
  const double lambda = (-1 + std::sqrt(1 + a2 * tan2)) / 2;
  const double g2 = 1 / (1 + 2 * lambda);
  const double s = std::pow(1 - std::cos(theta_d), 5);
  double f[3];
  for (int c = 0; c < 3; ++c) f[c] = (f0[c] + (1 - f0[c]) * s) * d * g2 / (4 * cos_io * cos_io);
  return luma(f[0], f[1], f[2]);
}

TEST(Slice, RoughConductorPixelsShowTheClosedFormOnTheBar) {
  const double alpha = 0.3, f0[3] = {0.9, 0.6, 0.3};
  const BxDF rc = parse_material(R"({"type":"roughconductor","alpha":0.3,"fresnel":"schlick","f0":[0.9,0.6,0.3]})");
  SliceOptions o;
  o.size = kSize;
  o.lo = 1e-3, o.hi = 100;  // a fixed scale: every value below lies inside it
  const SliceFigure fig = make_slice(rc, nullptr, o);
  for (const double th : {1.0, 10.0, 20.0, 35.0, 50.0, 70.0})
    for (const double td : {5.0, 30.0, 60.0, 80.0}) {
      const double y = ggx_schlick_luminance(alpha, f0, centre_theta_h(th) * kDeg, centre_theta_d(td) * kDeg);
      ASSERT_GT(y, o.lo);
      ASSERT_LT(y, o.hi);
      EXPECT_LT(code_distance(pixel_at(fig, 0, th, td), bar_colour_of_value(fig, y)), kBarTolerance)
          << "θh " << th << " θd " << td << " Y " << y;
    }
  // On the √θh axis the pixel at u shows θh = u² · 90°.
  o.theta_h_axis = ThetaHAxis::Sqrt;
  const SliceFigure sq = make_slice(rc, nullptr, o);
  for (const double u : {0.1, 0.3, 0.6, 0.9}) {
    const Rect& p = sq.panels[0];
    const int px = int(u * kSize), py = kSize / 2;
    const double uc = (px + 0.5) / kSize, td = (1 - (py + 0.5) / kSize) * 90;
    const double y = ggx_schlick_luminance(alpha, f0, uc * uc * kPiD / 2, td * kDeg);
    EXPECT_LT(code_distance(sq.image.at(p.x + px, p.y + py), bar_colour_of_value(sq, y)), kBarTolerance) << "u " << u;
  }
  // The automatic scale: whole decades around the 1st and 99th percentiles of the values
  // at the pixel centres (here from 10^-2.x to 10^0.x; the top row's 1/cos θ growth, up
  // to 10^1.x, lies beyond the 99th).
  std::vector<double> ys;
  for (int py = 0; py < kSize; ++py)
    for (int px = 0; px < kSize; ++px)
      ys.push_back(ggx_schlick_luminance(alpha, f0, (px + 0.5) / kSize * kPiD / 2, (1 - (py + 0.5) / kSize) * kPiD / 2));
  std::sort(ys.begin(), ys.end());
  const double p01 = ys[size_t(0.01 * double(ys.size() - 1))], p99 = ys[size_t(0.99 * double(ys.size() - 1))];
  const SliceFigure automatic = make_slice(rc, nullptr, SliceOptions{.size = kSize});
  EXPECT_DOUBLE_EQ(automatic.hi, std::pow(10.0, std::ceil(std::log10(p99))));
  EXPECT_DOUBLE_EQ(automatic.lo, std::pow(10.0, std::floor(std::log10(p01))));
  EXPECT_LT(automatic.hi, ys.back());
  // The specular peak: the θh = 0 column is brighter than θh = 60° at every θd below 80°.
  for (const double td : {5.0, 30.0, 60.0, 80.0})
    EXPECT_GT(luminance(pixel_at(fig, 0, 0, td)), 1.5 * luminance(pixel_at(fig, 0, 60, td))) << td;
}

TEST(Slice, HorizonIsGreyExactlyWhereWiDips) {
  // At φd = 0 and φh = 0, wi = (sin(θh + θd), 0, cos(θh + θd)) and wo = (sin(θh − θd), 0,
  // cos(θh − θd)): wi is below the horizon exactly where θh + θd > 90°.
  const BxDF diffuse = parse_material(R"({"type":"diffuse"})");
  SliceOptions o;
  o.size = kSize;
  o.phi_d = 0;
  const SliceFigure fig = make_slice(diffuse, nullptr, o);
  const Rect& p = fig.panels[0];
  int grey = 0;
  for (int py = 0; py < p.height; ++py)
    for (int px = 0; px < p.width; ++px) {
      const double th = (px + 0.5) / kSize * 90, td = (1 - (py + 0.5) / kSize) * 90;
      if (std::abs(th + td - 90) < 0.5) continue;  // on the line itself: rounding decides
      const bool below = th + td > 90;
      grey += below;
      ASSERT_EQ(is_horizon(fig.image.at(p.x + px, p.y + py)), below) << th << " " << td;
    }
  EXPECT_GT(grey, kSize * kSize / 3);
  // At φd = 180° the roles swap: wo = (sin(θh + θd), 0, cos(θh + θd)) dips.
  o.phi_d = kPiD;
  const SliceFigure swapped = make_slice(diffuse, nullptr, o);
  for (int py = 0; py < p.height; ++py)
    for (int px = 0; px < p.width; ++px) {
      const double th = (px + 0.5) / kSize * 90, td = (1 - (py + 0.5) / kSize) * 90;
      if (std::abs(th + td - 90) < 0.5) continue;
      ASSERT_EQ(is_horizon(swapped.image.at(p.x + px, p.y + py)), th + td > 90) << th << " " << td;
    }
  // At φd = 90° both directions stay above the horizon everywhere.
  o.phi_d = kPiD / 2;
  const SliceFigure up = make_slice(diffuse, nullptr, o);
  for (int py = 0; py < kSize; ++py)
    for (int px = 0; px < kSize; ++px) ASSERT_FALSE(is_horizon(up.image.at(up.panels[0].x + px, up.panels[0].y + py)));
}

TEST(Slice, CompareWithItselfIsZeroDifference) {
  const BxDF rc = parse_material(R"({"type":"roughconductor","alpha":0.2,"material":"Au"})");
  SliceOptions o;
  o.size = kSize;
  const SliceFigure fig = make_slice(rc, &rc, o);
  ASSERT_EQ(fig.panels.size(), 3u);
  ASSERT_TRUE(fig.diff_bar);
  EXPECT_DOUBLE_EQ(fig.diff_range, 0.01);  // the smallest automatic scale
  const Rect& d = fig.panels[2];
  const Color zero = from_srgb(0.95, 0.95, 0.95);  // diverging_colormap(0), the docs' "no difference"
  for (int py = 0; py < d.height; ++py)
    for (int px = 0; px < d.width; ++px) ASSERT_LT(code_distance(fig.image.at(d.x + px, d.y + py), zero), 1e-6);
  // The two value panels are the same image.
  for (int py = 0; py < kSize; ++py)
    for (int px = 0; px < kSize; ++px)
      ASSERT_EQ(fig.image.at(fig.panels[0].x + px, fig.panels[0].y + py),
                fig.image.at(fig.panels[1].x + px, fig.panels[1].y + py));
}

TEST(Slice, DifferenceOfTwoDiffuseMaterialsIsTheirRatioLessOne) {
  // f_b / f_a = 0.6 / 0.5: +20% everywhere, the top of the automatic ±20% scale; the other
  // way round −16.7%.
  const BxDF a = parse_material(R"({"type":"diffuse","reflectance":0.5})");
  const BxDF b = parse_material(R"({"type":"diffuse","reflectance":0.6})");
  SliceOptions o;
  o.size = kSize;
  const SliceFigure up = make_slice(a, &b, o);
  EXPECT_DOUBLE_EQ(up.diff_range, 0.2);
  EXPECT_LT(code_distance(pixel_at(up, 2, 45, 45), bar_colour_of_difference(up, 0.2)), kBarTolerance);
  const SliceFigure down = make_slice(b, &a, o);
  EXPECT_DOUBLE_EQ(down.diff_range, 0.2);
  EXPECT_LT(code_distance(pixel_at(down, 2, 45, 45), bar_colour_of_difference(down, 0.5 / 0.6 - 1)), kBarTolerance);
  EXPECT_GT(code_distance(pixel_at(down, 2, 45, 45), bar_colour_of_difference(down, -0.2)), kBarTolerance);
  // A fixed scale: +20% is then half-way up a ±40% bar.
  o.diff_range = 0.4;
  const SliceFigure fixed = make_slice(a, &b, o);
  EXPECT_LT(code_distance(pixel_at(fixed, 2, 45, 45), bar_colour_of_difference(fixed, 0.2)), kBarTolerance);
}

TEST(Slice, BadOptionsAndSpecularMaterialsAreInputErrors) {
  const BxDF diffuse = parse_material(R"({"type":"diffuse"})");
  SliceOptions o;
  o.size = 8;
  EXPECT_THROW(make_slice(diffuse, nullptr, o), InputError);
  o = {};
  o.size = kSize;
  o.phi_d = std::nan("");
  EXPECT_THROW(make_slice(diffuse, nullptr, o), InputError);
  o.phi_d = 1;
  o.lo = 1, o.hi = 0.5;
  EXPECT_THROW(make_slice(diffuse, nullptr, o), InputError);
  o.lo = o.hi = 0;
  o.diff_range = -1;
  EXPECT_THROW(make_slice(diffuse, &diffuse, o), InputError);
  // A mirror's f is 0 off its delta: nothing to scale automatically.
  const BxDF mirror = parse_material(R"({"type":"mirror"})");
  EXPECT_THROW(make_slice(mirror, nullptr, SliceOptions{}), InputError);
}

TEST(SliceColormap, SequentialLuminanceRisesAndDivergingFallsAwayFromZero) {
  double last = -1;
  for (int i = 0; i <= 1000; ++i) {
    const double y = luminance(sequential_colormap(i / 1000.0));
    ASSERT_GT(y, last) << i;
    last = y;
  }
  const double centre = luminance(diverging_colormap(0));
  for (int i = 1; i <= 100; ++i) {
    ASSERT_LT(luminance(diverging_colormap(i / 100.0)), luminance(diverging_colormap((i - 1) / 100.0))) << i;
    ASSERT_LT(luminance(diverging_colormap(-i / 100.0)), luminance(diverging_colormap(-(i - 1) / 100.0))) << i;
  }
  EXPECT_GT(centre, 0.8);
  // Blue below, red above; the horizon grey is in neither map.
  EXPECT_GT(diverging_colormap(-1)[2], diverging_colormap(-1)[0]);
  EXPECT_GT(diverging_colormap(1)[0], diverging_colormap(1)[2]);
  const Color grey = from_srgb(kSliceHorizon[0], kSliceHorizon[1], kSliceHorizon[2]);
  for (int i = 0; i <= 100; ++i) {
    EXPECT_GT(code_distance(sequential_colormap(i / 100.0), grey), 0.1);
    EXPECT_GT(code_distance(diverging_colormap(2 * i / 100.0 - 1), grey), 0.1);
  }
}

TEST(SliceFont, LabelCharactersHaveDistinctGlyphs) {
  const std::u32string used = U"0123456789.-+%()/=: \u03b8\u03c6\u00b0ABYabcdefghijklmnopqrstuvwxyz";
  std::set<std::string> bitmaps;
  for (const char32_t c : used) {
    ASSERT_TRUE(has_glyph(c)) << int(c);
    std::string bits;
    for (int r = 0; r < kGlyphHeight; ++r)
      for (int k = 0; k < kGlyphWidth; ++k) bits += glyph_pixel(c, k, r) ? '#' : '.';
    EXPECT_TRUE(bitmaps.insert(bits).second) << "glyph of U+" << std::hex << int(c) << " repeats another";
    if (c != U' ') {
      EXPECT_NE(bits.find('#'), std::string::npos) << int(c);
    }
  }
  EXPECT_FALSE(has_glyph(U'Q'));
  EXPECT_EQ(text_width("\u03b8h", 2), (2 * kGlyphAdvance - 1) * 2);  // θ is one character
}

}  // namespace
}  // namespace gonio::render
