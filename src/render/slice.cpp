// The θh × θd slice figure of slice.h: evaluate, pick the scales, draw panels, bars and
// labels.

#include "gonio/render/slice.h"

#include <algorithm>
#include <cstddef>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <tuple>
#include <utility>

#include "gonio/error.h"
#include "gonio/merl.h"
#include "gonio/render/bitmap_font.h"
#include "gonio/render/colormap.h"

namespace gonio::render {
namespace {

constexpr double kDeg = kPiD / 180;
constexpr double kBelowHorizon = kSliceBelowHorizon;

Color code(const double (&c)[3]) { return from_srgb(c[0], c[1], c[2]); }

// Position of value y on the log scale [lo, hi], clamped to [0, 1]; 0 for y = 0.
double log_position(double y, double lo, double hi) {
  if (!(y > 0)) return 0;
  return std::clamp((std::log10(y) - std::log10(lo)) / (std::log10(hi) - std::log10(lo)), 0.0, 1.0);
}

// 10^e as a label: 0.01 … 100 in decimals, else 1e-3, 1e3.
std::string decade_label(int e) {
  static const char* kNear[] = {"0.01", "0.1", "1", "10", "100"};
  if (e >= -2 && e <= 2) return kNear[e + 2];
  char buf[16];
  std::snprintf(buf, sizeof buf, "1e%d", e);
  return buf;
}

std::string short_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

// Relative difference as a percentage label: "-50%", "0", "+1%".
std::string percent_label(double v) {
  if (v == 0) return "0";
  char buf[32];
  std::snprintf(buf, sizeof buf, v > 0 ? "+%.3g%%" : "%.3g%%", 100 * v);
  return buf;
}

void fill(Image& img, const Rect& r, const Color& c) {
  for (int y = std::max(r.y, 0); y < std::min(r.y + r.height, img.height()); ++y)
    for (int x = std::max(r.x, 0); x < std::min(r.x + r.width, img.width()); ++x) img.at(x, y) = c;
}

// One-pixel frame just outside r.
void frame(Image& img, const Rect& r, const Color& ink) {
  fill(img, {r.x - 1, r.y - 1, r.width + 2, 1}, ink);
  fill(img, {r.x - 1, r.y + r.height, r.width + 2, 1}, ink);
  fill(img, {r.x - 1, r.y, 1, r.height}, ink);
  fill(img, {r.x + r.width, r.y, 1, r.height}, ink);
}

struct Style {
  int s;        // font scale
  int glyph_h;  // text height
  int tick;     // tick length
  int gap;
  Color ink, background, horizon;
};

// θh ticks under a panel and its axis label; θd ticks at its left when `theta_d_labels`.
void draw_axes(Image& img, const Rect& p, const SliceOptions& o, const Style& st, bool theta_d_labels) {
  const bool sq = o.theta_h_axis == ThetaHAxis::Sqrt;
  const std::vector<int> h_ticks = sq ? std::vector<int>{0, 10, 30, 60, 90} : std::vector<int>{0, 30, 60, 90};
  const int below = p.y + p.height + 1;
  for (const int deg : h_ticks) {
    const double u = sq ? std::sqrt(deg / 90.0) : deg / 90.0;
    const int x = std::min(p.x + int(std::lround(u * p.width)), p.x + p.width - 1);
    fill(img, {x, below, 1, st.tick}, st.ink);
    const std::string label = std::to_string(deg);
    draw_text(img, x - text_width(label, st.s) / 2, below + st.tick + st.gap, label, st.s, st.ink);
  }
  const std::string axis = sq ? "\u03b8h (deg, sqrt)" : "\u03b8h (deg)";
  draw_text(img, p.x + (p.width - text_width(axis, st.s)) / 2, below + st.tick + 2 * st.gap + st.glyph_h, axis,
            st.s, st.ink);
  for (const int deg : {0, 30, 60, 90}) {
    const int y = std::max(p.y + p.height - 1 - int(std::lround(deg / 90.0 * p.height)), p.y);
    fill(img, {p.x - 1 - st.tick, y, st.tick, 1}, st.ink);
    if (!theta_d_labels) continue;
    const std::string label = std::to_string(deg);
    draw_text(img, p.x - 1 - st.tick - st.gap - text_width(label, st.s), y - st.glyph_h / 2, label, st.s, st.ink);
  }
  if (theta_d_labels) {
    const std::string axis_d = "\u03b8d";
    const int x = p.x - 1 - st.tick - 2 * st.gap - text_width("90", st.s) - text_width(axis_d, st.s);
    draw_text(img, x, p.y + p.height / 2 - st.glyph_h / 2, axis_d, st.s, st.ink);
  }
}

// A vertical bar of `height` rows coloured by colour_at(t) with t from 1 (top) to 0.
template <typename F>
void draw_bar(Image& img, const Rect& r, F colour_at, const Style& st) {
  for (int row = 0; row < r.height; ++row) fill(img, {r.x, r.y + row, r.width, 1}, colour_at(1 - (row + 0.5) / r.height));
  frame(img, r, st.ink);
}

// A tick at fraction t (0 bottom, 1 top) of the bar, labelled at its right.
void bar_tick(Image& img, const Rect& r, double t, const std::string& label, const Style& st) {
  const int y = std::clamp(r.y + r.height - 1 - int(std::lround(t * (r.height - 1))), r.y, r.y + r.height - 1);
  const int x = r.x + r.width + 1;
  fill(img, {x, y, st.tick, 1}, st.ink);
  draw_text(img, x + st.tick + st.gap, y - st.glyph_h / 2, label, st.s, st.ink);
}

// Labels of the log bar: the whole decades in [lo, hi] (every second one beyond six),
// or lo and hi themselves when fewer than two decades fall inside.
std::vector<std::pair<double, std::string>> log_ticks(double lo, double hi) {
  const double a = std::log10(lo), b = std::log10(hi);
  const int first = int(std::ceil(a - 1e-9)), last = int(std::floor(b + 1e-9));
  std::vector<std::pair<double, std::string>> ticks;
  if (last - first >= 1) {
    const int step = last - first > 6 ? 2 : 1;
    for (int e = first; e <= last; e += step) ticks.push_back({(e - a) / (b - a), decade_label(e)});
  } else {
    ticks.push_back({0.0, short_number(lo)});
    ticks.push_back({1.0, short_number(hi)});
  }
  return ticks;
}

int widest(const std::vector<std::pair<double, std::string>>& ticks, int s) {
  int w = 0;
  for (const auto& t : ticks) w = std::max(w, text_width(t.second, s));
  return w;
}

}  // namespace

double slice_theta_h(double u, ThetaHAxis axis) {
  u = std::clamp(u, 0.0, 1.0);
  return (axis == ThetaHAxis::Sqrt ? u * u : u) * (kPiD / 2);
}

std::vector<double> slice_values(const BxDF& bxdf, const SliceOptions& o) {
  const int n = o.size;
  std::vector<double> y(size_t(n) * size_t(n));
  for (int py = 0; py < n; ++py) {
    const double theta_d = (1 - (py + 0.5) / n) * (kPiD / 2);
    for (int px = 0; px < n; ++px) {
      const double theta_h = slice_theta_h((px + 0.5) / n, o.theta_h_axis);
      const auto [wo, wi] = merl_directions(theta_h, theta_d, o.phi_d);
      double v = kSliceBelowHorizon;
      if (wo.z > 0 && wi.z > 0) {
        v = luminance(bxdf.f(wo, wi));
        if (!(v >= 0) || !std::isfinite(v)) v = 0;  // a model's NaN is not shown as a value
      }
      y[size_t(py) * size_t(n) + size_t(px)] = v;
    }
  }
  return y;
}

std::pair<double, double> slice_auto_scale(const std::vector<std::vector<double>>& values) {
  // Percentiles, not the extremes: a microfacet model's f grows like 1 / cos θ in the
  // top row (θd → 90°) and would otherwise push the whole slice into the bottom colours.
  std::vector<double> positive;
  for (const auto& v : values)
    for (const double y : v)
      if (y > 0) positive.push_back(y);
  if (positive.empty())
    throw InputError("slice: f is 0 at every pixel (a specular material has no finite f to show)");
  const auto at = [&](double q) {
    auto it = positive.begin() + std::ptrdiff_t(q * double(positive.size() - 1));
    std::nth_element(positive.begin(), it, positive.end());
    return *it;
  };
  const double high = at(kHighPercentile), low = at(kLowPercentile);
  const int top = int(std::ceil(std::log10(high) - 1e-9));
  const int bottom = std::clamp(int(std::floor(std::log10(low) + 1e-9)), top - kMaxDecades, top - 1);
  return {std::pow(10.0, bottom), std::pow(10.0, top)};
}

SliceFigure make_slice(const BxDF& a, const BxDF* b, const SliceOptions& o) {
  if (o.size < kMinSliceSize || o.size > kMaxSliceSize)
    throw InputError("slice: panel size " + std::to_string(o.size) + " is outside " + std::to_string(kMinSliceSize) +
                     " to " + std::to_string(kMaxSliceSize) + " pixels");
  if (!(o.phi_d >= 0 && o.phi_d <= kPiD))
    throw InputError("slice: phi_d " + format_number(o.phi_d / kDeg) + " degrees is outside 0 to 180");
  const bool auto_range = o.lo == 0 && o.hi == 0;
  if (!auto_range && !(o.lo > 0 && o.hi > o.lo && std::isfinite(o.hi)))
    throw InputError("slice: colour range " + format_number(o.lo) + " to " + format_number(o.hi) +
                     " must have 0 < low < high");
  if (!(o.diff_range >= 0 && std::isfinite(o.diff_range)))
    throw InputError("slice: difference range " + format_number(o.diff_range) + " must be > 0");

  std::vector<std::vector<double>> values = {slice_values(a, o)};
  if (b) values.push_back(slice_values(*b, o));

  // The shared log scale.
  double lo = o.lo, hi = o.hi;
  if (auto_range) {
    std::tie(lo, hi) = slice_auto_scale(values);
  }

  // The relative difference (f_b − f_a) / f_a per pixel; +∞ where only f_b is non-zero.
  std::vector<double> diff;
  double diff_range = o.diff_range;
  if (b) {
    diff.resize(values[0].size());
    double max_abs = 0;
    for (size_t i = 0; i < diff.size(); ++i) {
      const double ya = values[0][i], yb = values[1][i];
      if (ya == kBelowHorizon || yb == kBelowHorizon) {
        diff[i] = std::numeric_limits<double>::quiet_NaN();
        continue;
      }
      diff[i] = ya > 0 ? (yb - ya) / ya : yb > 0 ? std::numeric_limits<double>::infinity() : 0;
      max_abs = std::max(max_abs, std::abs(diff[i]));
    }
    if (diff_range == 0) {
      diff_range = 1;
      for (const double r : {0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0})
        if (max_abs <= r * (1 + 1e-6)) {  // f is float: +20% may come out as 0.2000001
          diff_range = r;
          break;
        }
    }
  }

  // Layout, in pixels. The font is scaled 2× on panels of 128 pixels and more.
  Style st;
  st.s = o.size >= 128 ? 2 : 1;
  st.glyph_h = kGlyphHeight * st.s;
  st.tick = 2 * st.s;
  st.gap = 2 * st.s;
  st.ink = code(kSliceInk);
  st.background = code(kSliceBackground);
  st.horizon = code(kSliceHorizon);
  // Panels of one row 12 font pixels apart: the 90 under one and the 0 under the next stay clear.
  const int margin = 4 * st.s, spacing = 8 * st.s, panel_gap = 12 * st.s, bar_w = 8 * st.s;
  const int left = margin + text_width("\u03b8d", st.s) + 2 * st.gap + text_width("90", st.s) + st.tick + 2;
  const int top = margin + st.glyph_h + 2 * st.gap;
  const int bottom = st.tick + 3 * st.gap + 2 * st.glyph_h + margin;
  const int n = o.size;

  SliceFigure fig;
  fig.lo = lo, fig.hi = hi, fig.diff_range = diff_range;
  int x = left;
  for (size_t k = 0; k < values.size(); ++k) {
    fig.panels.push_back({x, top, n, n});
    x += n + (k + 1 < values.size() ? panel_gap : spacing);
  }
  const auto ticks = log_ticks(lo, hi);
  const std::string bar_title = "f (1/sr)";
  fig.bar = {x, top, bar_w, n};
  x += std::max(bar_w + 1 + st.tick + st.gap + widest(ticks, st.s), text_width(bar_title, st.s)) + spacing;
  if (b) x += left - margin;  // room for the difference panel's θd labels
  std::vector<std::pair<double, std::string>> diff_ticks;
  const std::string diff_title = "(B-A)/A";
  if (b) {
    fig.panels.push_back({x, top, n, n});
    x += n + spacing;
    fig.diff_bar = Rect{x, top, bar_w, n};
    for (const double t : {-1.0, -0.5, 0.0, 0.5, 1.0}) diff_ticks.push_back({(t + 1) / 2, percent_label(t * diff_range)});
    x += std::max(bar_w + 1 + st.tick + st.gap + widest(diff_ticks, st.s), text_width(diff_title, st.s));
  }
  fig.image = Image(x + margin, top + n + bottom);
  Image& img = fig.image;
  fill(img, {0, 0, img.width(), img.height()}, st.background);

  // The value panels, then the difference.
  for (size_t k = 0; k < values.size(); ++k) {
    const Rect& p = fig.panels[k];
    for (int py = 0; py < n; ++py)
      for (int px = 0; px < n; ++px) {
        const double y = values[k][size_t(py) * size_t(n) + size_t(px)];
        img.at(p.x + px, p.y + py) = y == kBelowHorizon ? st.horizon : sequential_colormap(log_position(y, lo, hi));
      }
  }
  if (b) {
    const Rect& p = fig.panels[2];
    for (int py = 0; py < n; ++py)
      for (int px = 0; px < n; ++px) {
        const double d = diff[size_t(py) * size_t(n) + size_t(px)];
        img.at(p.x + px, p.y + py) = std::isnan(d) ? st.horizon : diverging_colormap(std::clamp(d / diff_range, -1.0, 1.0));
      }
  }

  // Frames, axes, titles.
  char phi[48];
  std::snprintf(phi, sizeof phi, "\u03c6d = %g\u00b0", std::round(o.phi_d / kDeg * 100) / 100);
  const std::vector<std::string> titles =
      b ? std::vector<std::string>{std::string("A, ") + phi, "B", diff_title} : std::vector<std::string>{std::string("f, ") + phi};
  for (size_t k = 0; k < fig.panels.size(); ++k) {
    const Rect& p = fig.panels[k];
    frame(img, p, st.ink);
    draw_axes(img, p, o, st, k == 0 || k == 2);
    draw_text(img, p.x, margin, titles[k], st.s, st.ink);
  }
  draw_bar(img, fig.bar, [](double t) { return sequential_colormap(t); }, st);
  for (const auto& [t, label] : ticks) bar_tick(img, fig.bar, t, label, st);
  draw_text(img, fig.bar.x, margin, bar_title, st.s, st.ink);
  if (b) {
    draw_bar(img, *fig.diff_bar, [](double t) { return diverging_colormap(2 * t - 1); }, st);
    for (const auto& [t, label] : diff_ticks) bar_tick(img, *fig.diff_bar, t, label, st);
  }
  return fig;
}

}  // namespace gonio::render
