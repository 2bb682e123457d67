#pragma once
// The explicit microsurface of the virtual gonioreflectometer (issue 13): a periodic
// height field z(x, y) sampled on an n × n grid over the square patch [0, size)². It is
// triangulated as two triangles per grid cell (lower-left triangle: vertices (i, j),
// (i+1, j), (i, j+1); upper-right: (i+1, j), (i+1, j+1), (i, j+1)), with indices taken
// modulo n, so the surface tiles the plane seamlessly. Each triangle's slopes are then
// exact forward differences of z, and every triangle has the same projected area
// (size/n)²/2: the area-weighted histogram of facet normals is the distribution of
// those differences (Walter et al. 2007 §3: D(m) cos θm is the projected-area density).

#include <cstdint>
#include <string>
#include <vector>

namespace gonio::measure {

struct HeightField {
  int n = 0;            // samples per side (the grid is n × n, periodic)
  double size = 1.0;    // side length of the patch, in the same unit as z
  std::vector<float> z; // z[i + n * j] at (x, y) = (i, j) · size / n

  double spacing() const { return size / n; }
  // Wraps i and j into [0, n).
  float at(int i, int j) const {
    const int ii = ((i % n) + n) % n;
    const int jj = ((j % n) + n) % n;
    return z[static_cast<std::size_t>(ii) + static_cast<std::size_t>(n) * jj];
  }
};

}  // namespace gonio::measure
