#pragma once
// How much of a MERL table (merl.h) is measured where it matters: the entries above the
// horizon that are missing. The measured model (measured_data.h) interpolates over a
// missing entry from its measured neighbours and reads f = 0 where all eight are missing,
// so a table with holes renders darker than its surface (issue 55): load_measured notes
// the fraction once (notes.h), and `gonio check` reports it.

#include "gonio/merl.h"

namespace gonio {

// Whether some part of bin (i, j, k) has both directions above the horizon: at its corner
// nearest the normal, tan θh tan θd |cos φd| < 1 (the heights
// cos θh cos θd ∓ sin θh sin θd cos φd both positive; bin edges as SPEC §2).
bool merl_entry_above_horizon(int i, int j, int k);

// The fraction of the entries above the horizon that are missing (0 for a full table).
double merl_missing_fraction(const MerlTable& table);

}  // namespace gonio
