#include "Mapping/Mapper.h"
#include "Mapping/MidiFile.h"
#include "Mapping/Posture.h"
#include <catch2/catch.hpp>

using namespace armadillo::mapping;

TEST_CASE("RangeLearner keeps the smallest and largest value", "[mapping]")
{
    RangeLearner r;
    double lo = 0, hi = 0;
    CHECK_FALSE(r.range(lo, hi));
    r.add(3.0);
    r.add(-2.0);
    r.add(1.0);
    REQUIRE(r.range(lo, hi));
    CHECK(lo == -2.0);
    CHECK(hi == 3.0);
}
