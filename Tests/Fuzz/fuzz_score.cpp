// Tactile score files (Tactile/Score.h parseScore), motor sets and pitches.
#include "FuzzTarget.h"
#include "Tactile/Score.h"

ARMADILLO_FUZZ_TARGET(score)
{
    const auto text = armadillo::fuzz::text(data, size);
    std::uint16_t mask = 0;
    (void)armadillo::tactile::parseMotorSet(text, mask);
    (void)armadillo::tactile::parsePitch(text);
    (void)armadillo::tactile::parseScore(text, "fuzz.score");
}
