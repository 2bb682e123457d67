// HeightField (include/gonio/measure/heightfield.h) is header-only; its generators are in
// gaussian_surface.cpp (the Gaussian random surface) and profiles.cpp (flat, V-grooves,
// image heights).
#include "gonio/measure/heightfield.h"
