// The board's calibration JSON (Link/Calibration.h parseCalibration).
#include "FuzzTarget.h"
#include "Link/Calibration.h"

ARMADILLO_FUZZ_TARGET(calibration)
{
    (void)armadillo::link::parseCalibration(armadillo::fuzz::text(data, size), "fuzz.json");
}
