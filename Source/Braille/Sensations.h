#pragma once
// How a braille cell becomes vibration on the 3×3 grid (thesis §4.2.1–4.2.6). Motor sets are
// bit masks over motorIndex(row, col) in the right-arm layout; the tactile engine mirrors the
// columns for the left arm, so nothing here depends on the arm.
#include "Braille/Cells.h"
#include "Core/Types.h"
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace armadillo::braille {

using MotorSet = std::uint16_t;   ///< bit i = motor index i (right-arm layout)

constexpr MotorSet motorBit(int row, int col) noexcept { return static_cast<MotorSet>(1u << core::motorIndex(row, col)); }

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

/// One burst of a cue (the shapes no letter row has, docs/BRAILLE.md "Cues"): `gain` × the
/// reading level; `soft` = no jump-start spike.
struct CueBurst {
    double at = 0.0;        ///< s after the cue starts
    double duration = 0.0;  ///< s
    MotorSet motors = 0;
    float gain = 1.0f;
    bool soft = false;
};
inline constexpr MotorSet kUndersideLine = motorBit(0, 1) | motorBit(1, 1) | motorBit(2, 1);
/// "Something begins" (a training trial, a timed message): the underside line swept wrist → elbow (0.3 s).
inline constexpr std::array<CueBurst, 3> kSweepCue {{{0.0, 0.1, motorBit(0, 1), 0.8f, true},
                                                     {0.1, 0.1, motorBit(1, 1), 0.8f, true},
                                                     {0.2, 0.1, motorBit(2, 1), 0.8f, true}}};
/// "Your turn" / "the end": the underside line tapped twice (0.34 s).
inline constexpr std::array<CueBurst, 2> kDoubleTapCue {{{0.0, 0.12, kUndersideLine, 0.8f, false}, {0.22, 0.12, kUndersideLine, 0.8f, false}}};
/// "A word gap": the underside line once, soft (0.15 s).
inline constexpr CueBurst kWordGapCue {0.0, 0.15, kUndersideLine, 0.6f, true};
/// "A message is waiting" (issue 35, docs/MQTT.md): all nine motors, two short soft pulses
/// (0.15 s on, 0.15 s off): no letter row lights more than one row, and the training's "right"
/// is one long hum and its "wrong" three buzzes of the outer columns.
inline constexpr std::array<CueBurst, 2> kMessageWaitingCue {{{0.0, 0.15, 0x1FF, 0.6f, true}, {0.3, 0.15, 0x1FF, 0.6f, true}}};

/// Motor numbers k = index + 1 of a set, e.g. "1,2,3"; "-" for the empty set.
std::string motorList(MotorSet set);
/// Number of motors that differ between two sets (the Hamming distance of §4.2.3).
int hammingDistance(MotorSet a, MotorSet b) noexcept;

} // namespace armadillo::braille
