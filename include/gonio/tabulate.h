#pragma once
// A material as a MERL table (`gonio tabulate`, SPEC §3): f at every bin centre of the
// half/difference grid (merl.h), the entries whose directions lie below the surface
// written as not measured (as in MERL's own files).

#include "gonio/bxdf.h"
#include "gonio/merl.h"

namespace gonio {

// Throws InputError when `model` cannot be written as a MERL table: it is anisotropic
// (the table is isotropic) or has a delta lobe (a table holds densities). A model that
// also transmits is tabulated by its reflection alone.
MerlTable tabulate(const BxDF& model);

}  // namespace gonio
