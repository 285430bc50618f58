// Answers without sight (Perkins chords) and the speech / braille display backends' capture.
#include "Access/BrailleDisplay.h"
#include "Access/Chords.h"
#include "Access/Speech.h"
#include "Common/Eventually.h"
#include "Common/FakeBrlApi.h"
#include "Core/AtomicFile.h"
#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <poll.h>
#include <unistd.h>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::access;

namespace {

/// Grade 1 letters a–z as dot numbers, written from the braille alphabet (World Braille Usage,
/// UNESCO 2013, the English/French base letters) — not from the code under test.
const char* const kLetterDots[26] = {"1",    "12",   "14",   "145",  "15",    "124",  "1245", "125",  "24",
                                     "245",  "13",   "123",  "134",  "1345",  "135",  "1234", "12345", "1235",
                                     "234",  "2345", "136",  "1236", "2456",  "1346", "13456", "1356"};

/// The key of each dot on the Perkins home row: dots 1 2 3 = F D S, dots 4 5 6 = J K L.
char keyOfDot(char dot)
{
    return "fdsjkl"[dot - '1'];
}

} // namespace

TEST_CASE("chords: S D F J K L are dots 3 2 1 4 5 6; groups are letters", "[chords]")
{
    braille::Dots d = 0;
    std::string why;
    // By hand from the Perkins layout: f = 1, d = 2, s = 3, j = 4, k = 5, l = 6.
    REQUIRE(chordDots("f", d, why));
    CHECK(d == 0x01);
    REQUIRE(chordDots("lkjsdf", d, why));
    CHECK(d == 0x3F);
    REQUIRE(chordDots("DF", d, why));
    CHECK(d == 0x03);
    CHECK_FALSE(chordDots("fa", d, why));
    CHECK(why.find("'a'") != std::string::npos);
    std::string letters;
    // Braille letters by hand: b = 12, e = 15, x = 1346, i = 24, t = 2345.
    REQUIRE(chordsToLetters("fd fk fsjl dj dsjk", letters, why));
    CHECK(letters == "bexit");
    CHECK_FALSE(chordsToLetters("fd s", letters, why));   // dot 3 alone is not a letter
    CHECK(why.find("dots 3") != std::string::npos);
    CHECK_FALSE(chordsToLetters("   ", letters, why));
    CHECK(letterChord('x') == "fsjl");
    CHECK(letterChord('a') == "f");
}

TEST_CASE("Perkins chords: every letter from its dots, keys released in any order", "[chords]")
{
    for (int i = 0; i < 26; ++i) {
        PerkinsChords c;
        std::string keys;
        for (const char* d = kLetterDots[i]; *d != '\0'; ++d) keys += keyOfDot(*d);
        for (char k : keys) CHECK(c.down(k));
        // Released in reverse: nothing until the last key comes up.
        for (std::size_t j = keys.size(); j-- > 1;) CHECK(c.up(keys[j]).kind == PerkinsChords::Event::Kind::None);
        const auto e = c.up(keys[0]);
        INFO("letter " << char('a' + i) << " keys " << keys);
        REQUIRE(e.kind == PerkinsChords::Event::Kind::Letter);
        CHECK(e.letter == 'a' + i);
        CHECK(! c.holding());
    }
    PerkinsChords c;
    CHECK(! c.down('a'));   // not a chord key
    CHECK(c.down('S'));     // either case
    const auto e = c.up('s');
    CHECK(e.kind == PerkinsChords::Event::Kind::NotLetter);   // dot 3 alone is no letter
    CHECK(e.why == "dots 3 is not a letter");
    CHECK(c.up('s').kind == PerkinsChords::Event::Kind::None);   // an up with nothing down
}

TEST_CASE("speech and braille display: capture backends record what a reader would hear and feel", "[speech]")
{
    const std::string dir = std::filesystem::temp_directory_path() / ("armadillo-access-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    std::string why;
    {
        auto s = makeSpeech("capture:" + dir + "/speech.txt", why);
        REQUIRE(s);
        s->say("which letter?", true);
        s->say("right", false);
        s->stop();
        s->setRate(40);
        auto b = makeBrailleDisplay("capture:" + dir + "/display.txt", why);
        REQUIRE(b);
        b->write("1/3 which letter?");
        CHECK(b->readKey().empty());
    }
    CHECK(readWholeFile(dir + "/speech.txt") == "say: which letter?\nsay+: right\nstop\nrate: 40\n");
    CHECK(readWholeFile(dir + "/display.txt") == "write: 1/3 which letter?\n");
    CHECK_FALSE(makeSpeech("klingon", why));
    CHECK(why.find("unknown speech backend") != std::string::npos);
    CHECK_FALSE(makeBrailleDisplay("nonsense", why));
    CHECK(makeSpeech("none", why) == nullptr);
    // BrlAPI with no server listening there: refused with a reason, no crash.
    why.clear();
    CHECK_FALSE(makeBrailleDisplay("brlapi:127.0.0.1:77", why));
    CHECK_FALSE(why.empty());
    std::filesystem::remove_all(dir);
}

TEST_CASE("braille display: the BrlAPI backend against a fake BrlAPI server — written text and typed keys", "[speech][brlapi]")
{
    test::FakeBrlApiServer server;
    REQUIRE(server.ok());
    std::string why;
    auto d = makeBrailleDisplay("brlapi:" + server.host(), why);
    INFO(why);
    if (!d && why.find("not found") != std::string::npos) {
        WARN("libbrlapi is not installed here (Debian: libbrlapi0.8): " + why);
        return;
    }
    REQUIRE(d);
    CHECK(d->name() == "brlapi");
    CHECK(server.enteredTty());
    d->write("3/10 which letter?");
    CHECK(armadillo::testing::eventually([&] { return !server.writes().empty(); }, 10.0));
    REQUIRE(!server.writes().empty());
    CHECK(server.writes().back() == "3/10 which letter?");
    // Keys typed on the display's braille keyboard come back as characters, Enter as "\n".
    server.type("b\n");
    std::string got;
    CHECK(armadillo::testing::eventually([&] {
        pollfd p {d->fd(), POLLIN, 0};
        if (::poll(&p, 1, 5) > 0)
            for (std::string k; !(k = d->readKey()).empty();) got += k;
        return got.size() >= 2;
    }, 10.0));
    CHECK(got == "b\n");
}
