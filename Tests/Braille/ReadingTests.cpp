#include "Braille/Reading.h"
#include <catch2/catch.hpp>

using namespace armadillo;
using namespace armadillo::braille;

namespace {
/// Letters of a document's units, in the order a sequence of steps visits them ("_" = word gap,
/// "|" = message gap, "$" = end), one entry per step.
std::string visit(ReadingCursor& c, const BrailleDocument& doc, const std::vector<bool>& directions)
{
    std::string s;
    for (bool forward : directions) {
        const ReadingStep step = c.advance(forward);
        switch (step.kind) {
        case StepKind::Cell: {
            const auto& u = c.units()[static_cast<std::size_t>(step.unit)];
            s += doc.messages[static_cast<std::size_t>(u.message)].symbols[static_cast<std::size_t>(u.symbol)].print;
            s += std::to_string(step.step + 1);
            break;
        }
        case StepKind::WordGap: s += "_"; break;
        case StepKind::MessageGap: s += "|"; break;
        case StepKind::TextEnd: s += "$"; break;
        }
        s += ' ';
    }
    return s;
}
} // namespace

TEST_CASE("Reading forward shows each character's rows wrist first, with word and message gaps", "[braille][reading]")
{
    const BrailleDocument doc = translateText("in it\nno", {});
    ReadingCursor c(layoutDocument(doc, DisplayMethod::Rows));
    REQUIRE(c.units().size() == 8);   // i n _ i t | n o
    CHECK(visit(c, doc, std::vector<bool>(22, true)) ==
          "i1 i2 i3 n1 n2 n3 _ i1 i2 i3 t1 t2 t3 | n1 n2 n3 o1 o2 o3 $ $ ");
}

TEST_CASE("Reading backward reverses the characters but keeps each character's rows in order", "[braille][reading]")
{
    // "HELLO" read backward is O L L E H (thesis §4.3.2), every letter row 1 → 3.
    const BrailleDocument doc = translateText("hello", {});
    ReadingCursor c(layoutDocument(doc, DisplayMethod::Rows));
    std::vector<bool> dirs(15, true);
    CHECK(visit(c, doc, dirs) == "h1 h2 h3 e1 e2 e3 l1 l2 l3 l1 l2 l3 o1 o2 o3 ");
    // Turning round: the character under the reader is felt whole again, then the ones behind.
    CHECK(visit(c, doc, std::vector<bool>(16, false)) == "o1 o2 o3 l1 l2 l3 l1 l2 l3 e1 e2 e3 h1 h2 h3 $ ");
    // From before the start, forward again starts with the first character.
    CHECK(visit(c, doc, {true, true}) == "h1 h2 ");
    // Turning mid-character restarts that character.
    CHECK(visit(c, doc, {false, false, false, false}) == "h1 h2 h3 $ ");
}

TEST_CASE("Other methods change the steps per character", "[braille][reading]")
{
    const BrailleDocument doc = translateText("an", {});
    ReadingCursor whole(layoutDocument(doc, DisplayMethod::WholeCharacter));
    CHECK(visit(whole, doc, {true, true, true}) == "a1 n1 $ ");
    ReadingCursor dots(layoutDocument(doc, DisplayMethod::DotByDot));
    CHECK(visit(dots, doc, std::vector<bool>(6, true)) == "a1 n1 n2 n3 n4 $ ");
}
