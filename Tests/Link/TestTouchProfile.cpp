// The touch profile file (docs/INTERFACES.md "Touch profile") and the gains made from it.
#include "Core/Errors.h"
#include "Link/TouchProfile.h"
#include <catch2/catch.hpp>

using namespace armadillo;
using namespace armadillo::core;
using namespace armadillo::link;

TEST_CASE("touch profile: written, read back, and gains = threshold / median", "[touchprofile]")
{
    TouchProfile p;
    p.threshold = {2, 4, 8, 4, 4, 1, 15, 3, 5};
    p.felt[6] = false;
    p.comfort = 7;
    p.arm = "left";
    p.stimuli = 120;
    p.stimulusSeconds = 90.0;
    const TouchProfile q = parseTouchProfile(touchProfileToJson(p), "mem");
    CHECK(q.threshold == p.threshold);
    CHECK(q.felt == p.felt);
    CHECK(q.comfort == 7);
    CHECK(q.arm == "left");
    CHECK(q.stimuli == 120);
    // Sorted thresholds 1 2 3 4 4 4 5 8 15: the median is 4. By hand: 2/4, 4/4, 8/4, …, 1/4,
    // 15/4 clamped to 4, 3/4, 5/4; motors 10.. stay 1.
    const auto g = touchProfileGains(q);
    const float expect[9] {0.5f, 1.0f, 2.0f, 1.0f, 1.0f, 0.25f, 3.75f, 0.75f, 1.25f};
    for (int m = 0; m < 9; ++m) CHECK(g[static_cast<std::size_t>(m)] == Approx(expect[m]));
    CHECK(g[9] == 1.0f);
    // Only "threshold" is needed; unknown keys are allowed.
    const TouchProfile minimal = parseTouchProfile("{\"threshold\": [3,3,3,3,3,3,3,3,3], \"note\": \"x\"}", "mem");
    CHECK(minimal.comfort == 0);
    for (float x : touchProfileGains(minimal)) CHECK(x == 1.0f);
}

TEST_CASE("touch profile: bad files are refused with the key named", "[touchprofile]")
{
    auto refuses = [](const std::string& json, const std::string& what) {
        try {
            parseTouchProfile(json, "p.json");
        } catch (const InputError& e) {
            INFO(e.what());
            CHECK(std::string(e.what()).find(what) != std::string::npos);
            return true;
        }
        return false;
    };
    CHECK(refuses("{}", "threshold"));
    CHECK(refuses("[]", "JSON object"));
    CHECK(refuses("{\"threshold\": [1,2,3]}", "9 levels"));
    CHECK(refuses("{\"threshold\": [1,2,3,4,5,6,7,8,16]}", "threshold[8]"));
    CHECK(refuses("{\"threshold\": [1,2,3,4,5,6,7,8,0]}", "threshold[8]"));
    CHECK(refuses("{\"threshold\": [1,2,3,4,5,6,7,8,2.5]}", "whole number"));
    CHECK(refuses("{\"threshold\": [1,2,3,4,5,6,7,8,\"x\"]}", "not a number"));
    CHECK(refuses("{\"format\": \"other\", \"threshold\": [1,2,3,4,5,6,7,8,9]}", "format"));
    CHECK(refuses("{\"version\": 2, \"threshold\": [1,2,3,4,5,6,7,8,9]}", "version"));
    CHECK(refuses("{\"threshold\": [1,2,3,4,5,6,7,8,9], \"felt\": [true]}", "felt"));
    CHECK(refuses("{\"threshold\": [1,2,3", "p.json"));
}
