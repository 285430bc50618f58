#include "Braille/Training.h"
#include "Core/AtomicFile.h"
#include "Core/Errors.h"
#include "TestArm.h"
#include <catch2/catch.hpp>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::braille;
using namespace armadillo::braille::test;

namespace {
std::vector<std::string> signWords()
{
    return readWordList(std::string(ARMADILLO_SOURCE_DIR) + "/Resources/Braille/signwords.txt");
}

std::vector<std::string> lines(const std::string& text)
{
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) out.push_back(l);
    return out;
}

/// Rolls the hanging arm by `steps` steps of 16°, feeding the session.
double rollAndFeed(TrainingSession& s, double t, double& roll, int steps)
{
    for (int i = 0; i < steps; ++i) {
        for (int k = 1; k <= 20; ++k) {
            const Eigen::Quaterniond q = poseToQuaternion(hanging(roll + 16.0 * k / 20.0));
            s.update(t, q * Eigen::Vector3d::UnitX(), q * Eigen::Vector3d::UnitY(), true);
            t += kDt;
        }
        roll += 16.0;
        const Eigen::Quaterniond q = poseToQuaternion(hanging(roll));
        for (int k = 0; k < 60; ++k, t += kDt) s.update(t, q * Eigen::Vector3d::UnitX(), q * Eigen::Vector3d::UnitY(), true);
    }
    return t;
}
} // namespace

TEST_CASE("The shipped list holds the thesis's 50 sign words", "[braille][training]")
{
    const auto words = signWords();
    CHECK(words.size() == 50);
    for (const char* w : {"ENTRANCE", "EXIT", "MEN", "WOMEN"}) CHECK(std::find(words.begin(), words.end(), w) != words.end());
    const std::string bad = std::string(ARMADILLO_BINARY_DIR) + "/braille-bad-words.txt";
    writeFileAtomically(bad, "EXIT\nEX1T\n");
    CHECK_THROWS_AS(readWordList(bad), InputError);
    writeFileAtomically(bad, "# only a comment\n");
    CHECK_THROWS_AS(readWordList(bad), InputError);
    std::remove(bad.c_str());
}

TEST_CASE("The letter sets of §4.4.1 come from the cells", "[braille][training]")
{
    CHECK(oneDotPerRowLetters() == std::vector<char> {'l', 'o', 's'});
    CHECK(gapLetters() == std::vector<char> {'k', 'm', 'u', 'x'});
}

TEST_CASE("The protocol follows the thesis's order and is repeatable from its seed", "[braille][training]")
{
    TrainingOptions o;
    o.trialsPerStage = 5;
    o.signWords = signWords();
    o.seed = 42;
    TrainingSession a(o), b(o);
    REQUIRE(a.trials().size() == 6 * 5 + 1);
    for (std::size_t i = 0; i < a.trials().size(); ++i) CHECK(a.trials()[i].expected == b.trials()[i].expected);
    CHECK(a.trials()[0].stage == TrainingStage::Sides);
    CHECK(a.trials()[5].stage == TrainingStage::Hold);
    CHECK(a.trials()[20].stage == TrainingStage::Alphabet);
    CHECK(a.trials()[20].units.size() == 26);
    CHECK(a.trials().back().stage == TrainingStage::Words);
    for (const auto& t : a.trials()) {
        if (t.stage == TrainingStage::Sides) CHECK((t.expected == "left" || t.expected == "right" || t.expected == "both"));
        if (t.stage == TrainingStage::OneDotPerRow) CHECK(std::string("los").find(t.expected) != std::string::npos);
        if (t.stage == TrainingStage::Gaps) CHECK(std::string("kmux").find(t.expected) != std::string::npos);
    }
    o.seed = 43;
    TrainingSession c(o);
    bool differs = false;
    for (std::size_t i = 0; i < a.trials().size(); ++i) differs = differs || a.trials()[i].expected != c.trials()[i].expected;
    CHECK(differs);
    o.signWords.clear();
    CHECK_THROWS_AS(TrainingSession(o), InputError);
}

TEST_CASE("Every movement, displayed row and answer is logged with its time", "[braille][training]")
{
    TrainingOptions o;
    o.stages = {TrainingStage::Hold, TrainingStage::Letters};
    o.trialsPerStage = 1;
    o.seed = 5;
    TrainingSession s(o);
    REQUIRE(s.trials().size() == 2);
    const int holdRow = s.trials()[0].holdRow;
    REQUIRE(holdRow >= 1);
    REQUIRE(holdRow <= 3);

    double t = 0.0, roll = 0.0;
    s.start(t);
    t = rollAndFeed(s, t, roll, 3 + holdRow);   // one full cell, then stop on the asked row
    CHECK(s.answer(t, "Here "));
    const std::string letter = s.trials()[1].expected;
    t = rollAndFeed(s, t, roll, 2);
    CHECK_FALSE(s.answer(t + 1.0, letter == "q" ? "z" : "q"));
    CHECK(s.finished());
    CHECK(s.correctCount() == 1);
    CHECK(s.answeredCount() == 2);

    const auto rows = lines(s.logCsv());
    REQUIRE(rows.size() > 10);
    CHECK(rows[0] == "t,event,stage,trial,expected,prompt,posture,roll_deg,unit,step,motors,answer,correct");
    int moves = 0, shown = 0, answers = 0, trials = 0;
    double lastT = -1.0;
    for (std::size_t i = 1; i < rows.size(); ++i) {
        const std::string& r = rows[i];
        const double rt = std::stod(r.substr(0, r.find(',')));
        CHECK(rt >= lastT);   // time never goes backwards
        lastT = rt;
        moves += r.find(",move,") != std::string::npos;
        shown += r.find(",row,") != std::string::npos;
        answers += r.find(",answer,") != std::string::npos;
        trials += r.find(",trial,") != std::string::npos;
    }
    CHECK(shown == 3 + holdRow + 2);
    CHECK(answers == 2);
    CHECK(trials == 2);
    CHECK(moves >= 8 * (3 + holdRow + 2));   // a row for every degree or two of roll
    CHECK(rows.back().find(",end,") != std::string::npos);

    const std::string path = std::string(ARMADILLO_BINARY_DIR) + "/braille-training-log.csv";
    s.saveLog(path);
    CHECK(readWholeFile(path) == s.logCsv());
    std::remove(path.c_str());
    CHECK_THROWS(s.saveLog("/nonexistent-dir/log.csv"));
}

TEST_CASE("Holding on the wrong row is scored wrong", "[braille][training]")
{
    TrainingOptions o;
    o.stages = {TrainingStage::Hold};
    o.trialsPerStage = 1;
    o.seed = 11;
    TrainingSession s(o);
    const int holdRow = s.trials()[0].holdRow;
    double t = 0.0, roll = 0.0;
    t = rollAndFeed(s, t, roll, 3 + (holdRow % 3) + 1);   // a different row of the second cell
    CHECK_FALSE(s.answer(t, "here"));
}

TEST_CASE("training: the §5.3 sign shorthand is each word's shortest unique prefix", "[training][signs]")
{
    // Worked by hand: ENTRANCE/EXIT share "e" (thesis §5.3: "EN" and "EX"); MEN is the start of
    // MENU, so it keeps its whole word; DO NOT ENTER is letters only.
    const auto t = signShorthand({"ENTRANCE", "EXIT", "MEN", "MENU", "WOMEN", "DO NOT ENTER", "exit"});
    using P = std::pair<std::string, std::string>;
    const std::vector<P> expect {{"en", "entrance"}, {"ex", "exit"}, {"men", "men"}, {"menu", "menu"}, {"w", "women"}, {"d", "donotenter"}};
    CHECK(t == expect);
    // The shipped list: every shorthand is unique and no longer than its word.
    const auto shipped = signShorthand(defaultSignWords());
    std::set<std::string> seen;
    for (const auto& [s, w] : shipped) {
        CHECK(seen.insert(s).second);
        CHECK(w.compare(0, s.size(), s) == 0);
    }
}

TEST_CASE("training: Grade 2 contractions are single cells; signs, contractions and the dots method in a plan", "[training][signs]")
{
    const auto words = contractionWords();
    // UEB: "and" = dots 12346, "the" = 2346, "but" = the letter b alone (alphabetic wordsign).
    for (const char* w : {"and", "the", "but", "can", "you"}) CHECK(std::find(words.begin(), words.end(), w) != words.end());
    TranslationOptions g2;
    g2.grade = 2;
    CHECK(translateText("and", g2).messages.at(0).symbols.at(0).cells.at(0) == dotsFromNumbers("12346"));
    for (const auto& w : words) CHECK(translateText(w, g2).cellCount() == 1);

    TrainingOptions o;
    o.stages = {TrainingStage::Signs, TrainingStage::Contractions, TrainingStage::Letters};
    o.trialsPerStage = 5;
    o.signWords = {"ENTRANCE", "EXIT"};
    o.method = DisplayMethod::DotByDot;
    const TrainingSession s(o);
    REQUIRE(s.trials().size() == 15);
    for (int i = 0; i < 5; ++i) {
        const TrainingTrial& t = s.trials()[static_cast<std::size_t>(i)];
        CHECK((t.expected == "entrance" || t.expected == "exit"));
        REQUIRE(t.units.size() == 2);   // "en" or "ex": two cells
    }
    for (int i = 5; i < 10; ++i) CHECK(s.trials()[static_cast<std::size_t>(i)].units.size() == 1);   // one cell
    // One dot at a time: a letter's steps are its raised dots, each a single motor.
    for (int i = 10; i < 15; ++i) {
        const TrainingTrial& t = s.trials()[static_cast<std::size_t>(i)];
        const Dots d = t.units.at(0).cell;
        CHECK(t.units.at(0).steps.size() == dotNumbers(d).size());
        for (MotorSet m : t.units.at(0).steps) CHECK(__builtin_popcount(m) == 1);
    }
}
