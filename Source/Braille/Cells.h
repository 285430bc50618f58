#pragma once
// Braille cells: text → cells with liblouis (Grade 1 uncontracted by default, Grade 2 contracted
// on request, any liblouis table), and Braille ASCII (.brf) files read directly (thesis §4.2,
// ARMADILLO.md §7). A cell is six dots, bit d-1 = dot d:
//
//      dot 1 ● ● dot 4      row 1 (the wrist on the display)
//      dot 2 ● ● dot 5      row 2
//      dot 3 ● ● dot 6      row 3 (toward the elbow)
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace armadillo::braille {

using Dots = std::uint8_t;   ///< bit d-1 set = dot d raised (d = 1..6); 0 = blank cell

constexpr Dots dot(int d) noexcept { return static_cast<Dots>(1u << (d - 1)); }
/// Dots from their numbers written as digits, e.g. dotsFromNumbers("1345") = N. Throws
/// std::invalid_argument for anything but digits 1..6.
Dots dotsFromNumbers(std::string_view numbers);
/// "1345" for N; "0" for the blank cell (the usual way braille tables write it).
std::string dotNumbers(Dots cell);
/// The Unicode braille pattern (U+2800 + dots) as UTF-8, e.g. "⠝" for N.
std::string unicodeCell(Dots cell);

/// A group of cells and the print text they stand for: one letter → one cell, a Grade 2
/// contraction ("the") → one cell for several letters, a capital → capital sign + letter.
struct BrailleSymbol {
    std::string print;          ///< UTF-8 source text ("" for cells the translator added)
    std::vector<Dots> cells;    ///< never empty; a single blank cell for a space
    bool isSpace() const noexcept { return cells.size() == 1 && cells.front() == 0; }
};

/// A message is one sign, one text message or one paragraph of a book.
struct BrailleMessage {
    std::vector<BrailleSymbol> symbols;
};

struct BrailleDocument {
    std::vector<BrailleMessage> messages;
    std::string table;          ///< the liblouis table list used, or "brf" for Braille ASCII input
    std::size_t cellCount() const noexcept;
};

struct TranslationOptions {
    int grade = 1;              ///< 1 = uncontracted (the thesis's), 2 = contracted
    std::string table;          ///< a liblouis table list; empty = the default of `grade`
    /// false (default): letters are shown as the thesis shows them — no capital signs, so
    /// "EXIT" reads E X I T. true: the table's capital indicators are kept.
    bool capitals = false;
    /// What the text is called in messages: "text" for --text, the file's path for @FILE.
    std::string source = "text";
};

/// The liblouis table a grade uses when no table is given: Unified English Braille
/// (en-ueb-g1.ctb uncontracted, en-ueb-g2.ctb contracted).
std::string defaultTable(int grade);

/// Translates UTF-8 text. Each line of the text is one message; spaces separate words.
/// Throws InputError (source "text") for a bad table, a grade other than 1 or 2, invalid UTF-8,
/// a character the table cannot translate (naming it and its position) or a table that needs
/// dots 7–8, which a three-row display cannot show.
BrailleDocument translateText(std::string_view utf8, const TranslationOptions& options = {});

/// Braille ASCII (North American .brf): each of the 64 characters 0x20..0x5F is one cell;
/// lower case and `{|}~ are accepted as their upper-case forms. Line breaks separate words;
/// blank lines and form feeds (page breaks) separate messages. Throws InputError naming `source`,
/// the line and the column for any other character.
BrailleDocument parseBrf(std::string_view content, const std::string& source);
BrailleDocument readBrfFile(const std::string& path);

/// Dots of one Braille ASCII character; false when `c` is not Braille ASCII.
bool brfToDots(char c, Dots& out) noexcept;
/// The upper-case Braille ASCII character of a cell (for writing .brf files).
char dotsToBrf(Dots cell) noexcept;

/// Reads SceneConfig::text: "@PATH" reads a file (".brf" as Braille ASCII, anything else as
/// UTF-8 text to translate); anything else is the text itself.
BrailleDocument loadDocument(const std::string& textOrFile, const TranslationOptions& options);

} // namespace armadillo::braille
