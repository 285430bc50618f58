#include "Access/Chords.h"
#include <array>

namespace armadillo::access {

namespace {
/// Key → dot, the Perkins layout on a QWERTY home row.
int keyDot(char k) noexcept
{
    switch (k) {
    case 'f': case 'F': return 1;
    case 'd': case 'D': return 2;
    case 's': case 'S': return 3;
    case 'j': case 'J': return 4;
    case 'k': case 'K': return 5;
    case 'l': case 'L': return 6;
    default: return 0;
    }
}

/// Grade 1 letters by cell, from liblouis (the same source as every displayed text).
const std::array<char, 64>& letterByCell()
{
    static const std::array<char, 64> table = [] {
        std::array<char, 64> t {};
        for (char c = 'a'; c <= 'z'; ++c) {
            const braille::BrailleDocument doc = braille::translateText(std::string(1, c), {});
            if (doc.cellCount() == 1) t[doc.messages[0].symbols[0].cells[0] & 63u] = c;
        }
        return t;
    }();
    return table;
}
} // namespace

bool chordDots(std::string_view keys, braille::Dots& dots, std::string& why)
{
    dots = 0;
    for (char k : keys) {
        const int d = keyDot(k);
        if (d == 0) {
            why = std::string("'") + k + "' is not a chord key (S D F J K L = dots 3 2 1 4 5 6)";
            return false;
        }
        dots = static_cast<braille::Dots>(dots | (1u << (d - 1)));
    }
    if (dots == 0) {
        why = "an empty chord";
        return false;
    }
    return true;
}

bool chordsToLetters(std::string_view line, std::string& letters, std::string& why)
{
    letters.clear();
    std::size_t at = 0;
    while (at < line.size()) {
        const std::size_t b = line.find_first_not_of(" \t", at);
        if (b == std::string_view::npos) break;
        const std::size_t e = std::min(line.find_first_of(" \t", b), line.size());
        const std::string_view group = line.substr(b, e - b);
        braille::Dots d = 0;
        if (!chordDots(group, d, why)) return false;
        const char c = letterByCell()[d & 63u];
        if (c == 0) {
            why = "chord '" + std::string(group) + "' (dots " + braille::dotNumbers(d) + ") is not a letter";
            return false;
        }
        letters += c;
        at = e;
    }
    if (letters.empty()) {
        why = "no chord typed";
        return false;
    }
    return true;
}

std::string letterChord(char letter)
{
    static const char kKeys[7] {0, 'f', 'd', 's', 'j', 'k', 'l'};
    for (int cell = 1; cell < 64; ++cell)
        if (letterByCell()[static_cast<std::size_t>(cell)] == letter) {
            std::string out;
            for (int dot = 1; dot <= 6; ++dot)
                if (cell & (1 << (dot - 1))) out += kKeys[dot];
            return out;
        }
    return "";
}

bool PerkinsChords::isChordKey(char key) noexcept { return keyDot(key) != 0; }

bool PerkinsChords::down(char key)
{
    const int d = keyDot(key);
    if (d == 0) return false;
    held_ |= 1u << (d - 1);
    chord_ = static_cast<braille::Dots>(chord_ | (1u << (d - 1)));
    return true;
}

PerkinsChords::Event PerkinsChords::up(char key)
{
    Event e;
    const int d = keyDot(key);
    if (d == 0 || (held_ & (1u << (d - 1))) == 0) return e;
    held_ &= ~(1u << (d - 1));
    if (held_ != 0 || chord_ == 0) return e;
    e.dots = chord_;
    chord_ = 0;
    // The letter of the cell through the same table the terminal's chords use (liblouis Grade 1).
    const char c = letterByCell()[e.dots & 63u];
    if (c != 0) {
        e.kind = Event::Kind::Letter;
        e.letter = c;
    } else {
        e.kind = Event::Kind::NotLetter;
        e.why = "dots " + braille::dotNumbers(e.dots) + " is not a letter";
    }
    return e;
}

} // namespace armadillo::access
