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

/// Chord entry from key down / key up events, as on a Perkins brailler (the app's Training panel,
/// Plugin/PerkinsKeys.h, feeds it from its key listener): the chord keys are pressed together, the
/// cell is every chord key that was down at any moment since the first went down, and it is taken
/// when the last one comes up. JUCE-free; one thread (the one that delivers the keys).
class PerkinsChords {
public:
    struct Event {
        enum class Kind { None, Letter, NotLetter };
        Kind kind = Kind::None;
        char letter = 0;          ///< Letter: a..z
        braille::Dots dots = 0;   ///< the chord's cell
        std::string why;          ///< NotLetter: "dots 3 6 is not a letter"
    };
    /// True when `key` is one of S D F J K L (either case).
    static bool isChordKey(char key) noexcept;
    /// A chord key went down (repeats are harmless). False for any other key.
    bool down(char key);
    /// A chord key came up: the chord's event once no chord key is down any more.
    Event up(char key);
    /// Forget a half-typed chord (focus lost, mode switched).
    void reset() noexcept { held_ = 0; chord_ = 0; }
    bool holding() const noexcept { return held_ != 0; }

private:
    unsigned held_ = 0;           ///< bit d-1: the key of dot d is down
    braille::Dots chord_ = 0;     ///< every dot pressed since the chord began
};

} // namespace armadillo::access
