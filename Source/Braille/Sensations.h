#pragma once
// How a braille cell becomes vibration on the 3×3 grid (thesis §4.2.1–4.2.6). Motor sets are
// bit masks over motorIndex(row, col) in the right-arm layout; the tactile engine mirrors the
// columns for the left arm, so nothing here depends on the arm.
#include "Braille/Cells.h"
#include "Core/Types.h"
#include <cstdint>
#include <string>
#include <vector>

namespace armadillo::braille {

using MotorSet = std::uint16_t;   ///< bit i = motor index i (right-arm layout)

constexpr MotorSet motorBit(int row, int col) noexcept { return static_cast<MotorSet>(1u << motorIndex(row, col)); }

/// The final method (§4.2.5–4.2.6): braille row r (0 = dots 1/4) on motor row r (0 = wrist);
/// the left dot on column 0, the right dot on column 2; both dots ⇒ left + centre + right (the
/// centre is the parity "serif", so the three non-empty row patterns differ pairwise by exactly
/// two motors); no dot ⇒ no motor (a pause).
MotorSet rowSensation(Dots cell, int row) noexcept;

/// The ways of showing one cell that the thesis compared (§4.2.1–4.2.5).
enum class DisplayMethod : std::uint8_t {
    Rows,            ///< §4.2.5: three row sensations, wrist row first (the final method)
    WholeCharacter,  ///< §4.2.1: every dot at once (dots 1–3 on column 0, 4–6 on column 2)
    ColumnPairs,     ///< §4.2.2: the left column (dots 1–3) on motor column 0, then the right on column 2
    DotByDot,        ///< §4.2.1: the cell drawn one dot at a time, dots 1..6 in order
};
inline constexpr int kDisplayMethodCount = 4;
const char* displayMethodName(DisplayMethod m) noexcept;   ///< "rows", "whole", "columns", "dots"
bool parseDisplayMethod(const std::string& name, DisplayMethod& out) noexcept;

/// The successive motor sets that show `cell` with `method` (an empty set = a pause step).
/// Rows always gives 3 steps; WholeCharacter 1; ColumnPairs 2; DotByDot one per raised dot
/// (1 for the blank cell).
std::vector<MotorSet> cellSteps(Dots cell, DisplayMethod method);

/// Motor numbers k = index + 1 of a set, e.g. "1,2,3"; "-" for the empty set.
std::string motorList(MotorSet set);
/// Number of motors that differ between two sets (the Hamming distance of §4.2.3).
int hammingDistance(MotorSet a, MotorSet b) noexcept;

} // namespace armadillo::braille
