#pragma once
// How much of a MERL table (merl.h) is measured where it matters: the entries above the
// horizon that are missing. The measured model (measured_data.h) interpolates over a
// missing entry from its measured neighbours and reads f = 0 where all eight are missing,
// so a table with holes renders darker than its surface (issue 55): load_measured notes
// the fraction once (notes.h), and `gonio check` reports it.

#include "gonio/merl.h"

namespace gonio {

// Whether the pair at bin (i, j, k)'s centre has both directions above the horizon:
// tan θh tan θd |cos φd| < 1 (their heights cos θh cos θd ∓ sin θh sin θd cos φd both
// positive; centres as merl.h). These are the entries that matter: the measured model
// interpolates between centres, so a point above the horizon always has the corner
// entry of smaller θh, θd and |cos φd| among its eight neighbours, itself above; and they
// are the entries `gonio tabulate` and MERL's own files fill (a bin the horizon cuts
// below its centre is written missing there).
bool merl_entry_above_horizon(int i, int j, int k);

// The fraction of the entries above the horizon that are missing (0 for a full table).
double merl_missing_fraction(const MerlTable& table);

}  // namespace gonio
