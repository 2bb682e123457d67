// gonio subsurface (SPEC §3): a semi-infinite slab of a `subsurface` material under a
// collimated beam at normal incidence; issue 14. Filled in by the subsurface work.

#include "commands.h"

namespace gonio::cli {

void register_subsurface(CLI::App&) {}

}  // namespace gonio::cli
