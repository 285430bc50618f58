#pragma once
// Small helpers the importers share to write score text (docs/TACTILE.md's format).
#include <cstdint>
#include <string>
#include <string_view>

namespace armadillo::formats::scoretext {

/// A plain decimal the score parser reads back exactly enough: up to `decimals` places, trailing
/// zeros dropped ("0.25", "3", "12.5").
std::string number(double v, int decimals = 6);
/// A `length`: rounded up (to a millionth and one more), so that it is never before the end of
/// a last event whose start and duration were each rounded to the nearest.
std::string lengthNumber(double v);
/// A motor set in the format's syntax: "1,3,7" (motors k = index + 1).
std::string motorSet(std::uint16_t mask);
/// A word usable as a part or cue name: lowercase letters, digits and '-' ("Piano RH" → "piano-rh");
/// `fallback` when nothing is left.
std::string name(std::string_view text, const std::string& fallback);
/// Text safe inside a '#' comment or a title (one line, printable).
std::string oneLine(std::string_view text);

} // namespace armadillo::formats::scoretext
