#include "Braille/Cells.h"
#include "Braille/Sensations.h"
#include "Core/Errors.h"
#include <catch2/catch.hpp>
#include <liblouis/liblouis.h>
#include <cctype>
#include <cstdio>
#include <fstream>
#include <map>
#include <random>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::braille;

namespace {
Dots singleCell(const std::string& text, int grade = 1)
{
    TranslationOptions o;
    o.grade = grade;
    const BrailleDocument doc = translateText(text, o);
    REQUIRE(doc.messages.size() == 1);
    REQUIRE(doc.messages[0].symbols.size() == 1);
    REQUIRE(doc.messages[0].symbols[0].cells.size() == 1);
    return doc.messages[0].symbols[0].cells[0];
}
} // namespace

TEST_CASE("All 26 Grade 1 letters give the thesis's row sensations", "[braille][cells]")
{
    // Motor numbers k = 3·row + col + 1 (row 0 = wrist; col 0 = left, 1 = centre, 2 = right):
    // written out by hand from the standard braille alphabet and §4.2.5 (left dot → left motor,
    // right dot → right motor, both → left + centre + right).
    const std::map<char, std::array<const char*, 3>> expected {
        {'a', {"1", "-", "-"}},         {'b', {"1", "4", "-"}},         {'c', {"1,2,3", "-", "-"}},
        {'d', {"1,2,3", "6", "-"}},     {'e', {"1", "6", "-"}},         {'f', {"1,2,3", "4", "-"}},
        {'g', {"1,2,3", "4,5,6", "-"}}, {'h', {"1", "4,5,6", "-"}},     {'i', {"3", "4", "-"}},
        {'j', {"3", "4,5,6", "-"}},     {'k', {"1", "-", "7"}},         {'l', {"1", "4", "7"}},
        {'m', {"1,2,3", "-", "7"}},     {'n', {"1,2,3", "6", "7"}},     {'o', {"1", "6", "7"}},
        {'p', {"1,2,3", "4", "7"}},     {'q', {"1,2,3", "4,5,6", "7"}}, {'r', {"1", "4,5,6", "7"}},
        {'s', {"3", "4", "7"}},         {'t', {"3", "4,5,6", "7"}},     {'u', {"1", "-", "7,8,9"}},
        {'v', {"1", "4", "7,8,9"}},     {'w', {"3", "4,5,6", "9"}},     {'x', {"1,2,3", "-", "7,8,9"}},
        {'y', {"1,2,3", "6", "7,8,9"}}, {'z', {"1", "6", "7,8,9"}},
    };
    REQUIRE(expected.size() == 26);
    for (const auto& [letter, rows] : expected) {
        INFO("letter " << letter);
        const Dots cell = singleCell(std::string(1, letter));
        for (int r = 0; r < 3; ++r) CHECK(motorList(rowSensation(cell, r)) == rows[static_cast<std::size_t>(r)]);
        // Every Grade 1 letter has a dot in row 1: "a pulse at the wrist" starts a character.
        CHECK(rowSensation(cell, 0) != 0);
        CHECK(cellSteps(cell, DisplayMethod::Rows).size() == 3);
    }
}

TEST_CASE("Any two non-empty row patterns differ by exactly two motors", "[braille][cells]")
{
    for (int row = 0; row < 3; ++row) {
        std::vector<MotorSet> patterns;
        for (int cell = 0; cell < 64; ++cell) {
            const MotorSet s = rowSensation(static_cast<Dots>(cell), row);
            if (s != 0 && std::find(patterns.begin(), patterns.end(), s) == patterns.end()) patterns.push_back(s);
            // Row r of a cell drives motors of motor row r only.
            for (int m = 0; m < kGridMotors; ++m)
                if (s & (1u << m)) CHECK(m / 3 == row);
        }
        REQUIRE(patterns.size() == 3);   // left, right, both
        for (std::size_t i = 0; i < patterns.size(); ++i)
            for (std::size_t j = i + 1; j < patterns.size(); ++j) CHECK(hammingDistance(patterns[i], patterns[j]) == 2);
    }
    CHECK(rowSensation(0, 0) == 0);   // an empty row is a pause
}

TEST_CASE("The older methods of §4.2.1-4.2.2 show the cell as the thesis describes", "[braille][cells]")
{
    const Dots n = dotsFromNumbers("1345");
    const auto whole = cellSteps(n, DisplayMethod::WholeCharacter);
    REQUIRE(whole.size() == 1);
    CHECK(motorList(whole[0]) == "1,3,6,7");   // dots 1,3 left; 4,5 right
    const auto columns = cellSteps(n, DisplayMethod::ColumnPairs);
    REQUIRE(columns.size() == 2);
    CHECK(motorList(columns[0]) == "1,7");
    CHECK(motorList(columns[1]) == "3,6");
    const auto dots = cellSteps(n, DisplayMethod::DotByDot);   // "at least four pulses" for N
    REQUIRE(dots.size() == 4);
    CHECK(motorList(dots[0]) == "1");
    CHECK(motorList(dots[1]) == "7");
    CHECK(motorList(dots[2]) == "3");
    CHECK(motorList(dots[3]) == "6");
    DisplayMethod m {};
    CHECK(parseDisplayMethod("columns", m));
    CHECK(m == DisplayMethod::ColumnPairs);
    CHECK_FALSE(parseDisplayMethod("bogus", m));
}

TEST_CASE("Grade 2 contractions from liblouis are single cells", "[braille][cells]")
{
    CHECK(singleCell("the", 2) == dotsFromNumbers("2346"));
    CHECK(singleCell("and", 2) == dotsFromNumbers("12346"));
    const BrailleDocument g1 = translateText("the", {});
    CHECK(g1.cellCount() == 3);   // uncontracted by default, as in the thesis

    TranslationOptions g2;
    g2.grade = 2;
    const BrailleDocument doc = translateText("the cat and the dog", g2);
    REQUIRE(doc.messages.size() == 1);
    const auto& symbols = doc.messages[0].symbols;
    REQUIRE(!symbols.empty());
    CHECK(symbols.front().print == "the");
    CHECK(symbols.front().cells.size() == 1);
    CHECK(doc.cellCount() < translateText("the cat and the dog", {}).cellCount());

    TranslationOptions table;
    table.table = "en-us-g2.ctb";   // table selectable; EBAE contracts "the" too
    CHECK(translateText("the", table).cellCount() == 1);
}

TEST_CASE("Text structure: words, messages and capitals", "[braille][cells]")
{
    const BrailleDocument doc = translateText("Do not enter\nEXIT", {});
    REQUIRE(doc.messages.size() == 2);
    int spaces = 0;
    for (const auto& s : doc.messages[0].symbols) spaces += s.isSpace() ? 1 : 0;
    CHECK(spaces == 2);
    CHECK(doc.messages[1].symbols.size() == 4);   // no capital signs by default: E X I T
    TranslationOptions caps;
    caps.capitals = true;
    CHECK(translateText("EXIT", caps).cellCount() > 4);
}

TEST_CASE("Text liblouis cannot translate and bad tables are refused clearly", "[braille][cells]")
{
    TranslationOptions bad;
    bad.table = "no-such-table.ctb";
    CHECK_THROWS_WITH(translateText("exit", bad), Catch::Contains("no-such-table.ctb"));
    CHECK_THROWS_AS(translateText("exit", bad), InputError);
    CHECK_THROWS_WITH(translateText("a\xE2\x98\x83", {}), Catch::Contains("U+2603"));   // a snowman
    CHECK_THROWS_WITH(translateText("a\xC3", {}), Catch::Contains("UTF-8"));
    TranslationOptions grade3;
    grade3.grade = 3;
    CHECK_THROWS_AS(translateText("a", grade3), InputError);
    TranslationOptions eightDot;
    eightDot.table = "en-us-comp8.ctb";
    eightDot.capitals = true;
    CHECK_THROWS_WITH(translateText("A", eightDot), Catch::Contains("dots 7-8"));
}

TEST_CASE("Braille ASCII agrees with liblouis's own .brf display table", "[braille][brf]")
{
    for (int cell = 0; cell < 64; ++cell) {
        widechar in = static_cast<widechar>(0x8000 | cell);   // LOU_DOTS
        widechar out = 0;
        REQUIRE(lou_dotsToChar("en-us-brf.dis", &in, &out, 1, 0));
        INFO("cell " << dotNumbers(static_cast<Dots>(cell)));
        CHECK(std::toupper(static_cast<int>(out)) == dotsToBrf(static_cast<Dots>(cell)));
        Dots back = 0xFF;
        REQUIRE(brfToDots(static_cast<char>(out), back));
        CHECK(back == cell);
    }
}

TEST_CASE("Braille ASCII files are read directly, with clear errors", "[braille][brf]")
{
    const BrailleDocument doc = parseBrf("EXIT\r\n\r\n,RE/ROOMS TO ! LEFT\r\n\f", "sign.brf");
    REQUIRE(doc.messages.size() == 2);
    CHECK(doc.messages[0].symbols.size() == 4);
    CHECK(doc.messages[0].symbols[1].cells[0] == dotsFromNumbers("1346"));   // X
    CHECK(doc.messages[1].symbols[0].cells[0] == dotsFromNumbers("6"));      // capital sign
    CHECK(doc.messages[1].symbols[3].cells[0] == dotsFromNumbers("34"));     // "st" sign '/'
    // Lower case is the same cell.
    CHECK(parseBrf("exit", "x").messages[0].symbols[2].cells[0] == dotsFromNumbers("24"));
    // A line break inside a paragraph is a word gap, not a new message.
    const BrailleDocument wrapped = parseBrf("DO NOT\nENT}", "x");
    CHECK(wrapped.messages.size() == 1);

    try {
        parseBrf("EXIT\nEX\tIT\n", "bad.brf");
        FAIL("a tab is not Braille ASCII");
    } catch (const InputError& e) {
        CHECK(e.file() == "bad.brf");
        CHECK(e.line() == 2);
        CHECK(std::string(e.what()).find("column 3") != std::string::npos);
    }
    CHECK_THROWS_AS(parseBrf("\n\n", "empty.brf"), InputError);
    CHECK_THROWS_AS(parseBrf("A\x80", "high.brf"), InputError);

    const std::string path = std::string(ARMADILLO_BINARY_DIR) + "/braille-test-sample.brf";
    {
        std::ofstream f(path, std::ios::binary);
        f << "MEN\n";
    }
    CHECK(loadDocument("@" + path, {}).cellCount() == 3);
    std::remove(path.c_str());
    CHECK_THROWS(loadDocument("@" + path, {}));
}

TEST_CASE("The shipped sample book reads", "[braille][brf]")
{
    const BrailleDocument doc = readBrfFile(std::string(ARMADILLO_SOURCE_DIR) + "/Resources/Braille/signs.brf");
    CHECK(doc.messages.size() >= 2);
}

TEST_CASE("Fuzz: any bytes either parse or are refused with an InputError", "[braille][fuzz]")
{
    std::mt19937_64 rng(2005);
    const std::string alphabet = "ABCXYZabcxyz ,;:!?'-#0123456789\n\r\f\t\x01\x7F\x80\xC3\xA9\xE2\x98\x83\xFF";
    int parsed = 0, refused = 0;
    for (int trial = 0; trial < 400; ++trial) {
        std::string s;
        const int n = static_cast<int>(rng() % 40);
        for (int i = 0; i < n; ++i)
            s += (rng() % 4 == 0) ? static_cast<char>(rng() % 256) : alphabet[rng() % alphabet.size()];
        for (int which = 0; which < 2; ++which) {
            try {
                const BrailleDocument doc = which == 0 ? parseBrf(s, "fuzz.brf") : translateText(s, {});
                for (const auto& m : doc.messages) {
                    CHECK_FALSE(m.symbols.empty());
                    for (const auto& sym : m.symbols) {
                        CHECK_FALSE(sym.cells.empty());
                        for (Dots d : sym.cells) CHECK(d < 64);   // six dots only
                    }
                }
                ++parsed;
            } catch (const InputError&) {
                ++refused;
            }
        }
    }
    CHECK(parsed > 0);
    CHECK(refused > 0);
}
