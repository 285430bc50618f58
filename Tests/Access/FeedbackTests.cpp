// The arm's right/wrong feedback (Access/Feedback.h) as docs/ACCESSIBILITY.md describes it: "right"
// = all nine motors hum softly together for 0.4 s; "wrong" = the two outer columns buzz three
// times. The masks are written out from the 3×3 grid (index = 3·row + col, col 1 = the underside
// line: motors 2, 5, 8), not taken from the code under test.
#include "Access/Feedback.h"
#include <catch2/catch.hpp>

using namespace armadillo::access;

TEST_CASE("arm feedback: right is one soft hum of all nine, wrong three buzzes of the outer columns", "[access][feedback]")
{
    constexpr std::uint16_t allNine = 0b111'111'111;
    constexpr std::uint16_t outer = 0b101'101'101;   // cols 0 and 2 of rows 0..2
    const auto right = feedbackSensation(true, 10.0f);
    REQUIRE(right.size() == 1);
    CHECK(right[0].motors == allNine);
    CHECK(right[0].duration == Approx(0.4));
    CHECK(right[0].soft);
    CHECK(right[0].level < 10.0f);   // softer than the reading level
    const auto wrong = feedbackSensation(false, 10.0f);
    REQUIRE(wrong.size() == 3);
    for (std::size_t i = 0; i < wrong.size(); ++i) {
        CHECK(wrong[i].motors == outer);
        CHECK(wrong[i].at == Approx(0.2 * static_cast<double>(i)));
        CHECK(wrong[i].duration == Approx(0.1));
        CHECK(wrong[i].level == 10.0f);
        CHECK(! wrong[i].soft);
    }
    CHECK(feedbackPause(false) > feedbackPause(true));
}
