#pragma once
// The one reading of a number on gonio's command line, for floating-point options, the
// numbers of stdin lines and --wavelength alike (docs/cli.md, "Numbers": decimal only).
// Integer options (decimal_in_range, below) take its integer subset: digits alone.

#include <cstdint>
#include <optional>
#include <string_view>

#include <CLI/CLI.hpp>

namespace gonio::cli {

// `text` read whole as a decimal number: an optional sign, digits with an optional
// point, an optional exponent ("-1.5", "+2", ".5", "1e-3"). Nothing else: no empty text,
// no spaces, no hexadecimal ("0x10") or hex-float ("0x1p-2"), which strtod and CLI11
// would take. "inf" and "nan" are returned as such, for the caller to name as not finite;
// a value beyond double's range is no number (nullopt).
std::optional<double> parse_decimal(std::string_view text);

// CLI11 check for a floating-point option (each value of a multi-value one): the text is
// a finite number by parse_decimal. Without it CLI11 reads "" as 0 and "0x10" as 16.
//   cmd.add_option("--theta", theta)->check(decimal_number());
CLI::Validator decimal_number();

// CLI11 transform for an integer option: decimal digits only (an optional sign, so that a
// negative value is reported as out of range), leading zeros dropped, and
// CLI::Range(lo, hi). CLI11's own conversion would also take 0x10, 0b11, 0o7 and 1e3,
// and read 010 as octal. Use it as
//   cmd.add_option("--seed", seed)->transform(decimal_in_range(0, kMaxSeed));
// with an integer type that holds the whole range (std::int64_t).
CLI::Validator decimal_in_range(std::int64_t lo, std::int64_t hi);

}  // namespace gonio::cli
