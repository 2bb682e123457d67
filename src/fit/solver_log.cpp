// Ceres reports through glog (gonio/fit/fit.h, quiet_solver_log).

#include <glog/logging.h>

#include "gonio/fit/fit.h"

namespace gonio {

void quiet_solver_log() {
  // A solve that fails at its starting point logs "Terminating: ..." at ERROR whatever
  // Solver::Options::logging_type says, and glog, never initialised, first prints
  // "WARNING: Logging before InitGoogleLogging() ...". The fit's outcome is gonio's to
  // report (one line), so only a FATAL message, a crash, still reaches stderr: glog drops
  // a message below minloglevel before writing anything, its own warning included.
  FLAGS_minloglevel = google::GLOG_FATAL;
  FLAGS_stderrthreshold = google::GLOG_FATAL;
}

}  // namespace gonio
