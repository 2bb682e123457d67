#include "gonio/bxdf/custom.h"

namespace gonio {

// Out of line so the vtable has one home.
CustomBxDF::~CustomBxDF() = default;

}  // namespace gonio
