#pragma once
// Answers without sight on an ordinary keyboard (issue 26): Perkins-style chord entry. The six
// keys S D F J K L stand for dots 3 2 1 4 5 6 (the home row under the fingers of a Perkins
// brailler: left ring, middle, index = dots 3, 2, 1; right index, middle, ring = dots 4, 5, 6).
// In a terminal a chord is typed as the group of its keys in any order ("fd" = dots 1+2 = b),
// cells separated by spaces, Enter submits the answer (docs/ACCESSIBILITY.md).
#include "Braille/Cells.h"
#include <string>
#include <string_view>

namespace armadillo::access {

/// The dots of one chord ("fd" → dots 1,2). False (and `why`) for any other key, or none.
bool chordDots(std::string_view keys, braille::Dots& dots, std::string& why);
/// A line of chords → the letters they are in Grade 1 ("fd f" → "ba"). False (and `why`, naming
/// the chord) for a bad key or a cell that is not a letter a–z.
bool chordsToLetters(std::string_view line, std::string& letters, std::string& why);
/// The chord keys of a letter a–z ("b" → "fd"), dots in the order 1..6 (for prompts and docs).
std::string letterChord(char letter);

} // namespace armadillo::access
