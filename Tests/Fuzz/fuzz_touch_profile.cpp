// The reader's touch profile JSON (Link/TouchProfile.h parseTouchProfile: per-motor thresholds).
#include "FuzzTarget.h"
#include "Link/TouchProfile.h"

ARMADILLO_FUZZ_TARGET(touch_profile)
{
    (void)armadillo::link::parseTouchProfile(armadillo::fuzz::text(data, size), "fuzz.json");
}
