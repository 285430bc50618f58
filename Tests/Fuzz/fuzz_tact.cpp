// bHaptics `.tact` files imported as a tactile score (importTact), for either forearm.
#include "Formats/ScoreImport.h"
#include "FuzzTarget.h"

ARMADILLO_FUZZ_TARGET(tact)
{
    armadillo::formats::HapticImportOptions options;
    if (size > 0 && (data[size - 1] & 1)) options.tactDevice = "ForearmL";
    (void)armadillo::formats::importTact(armadillo::fuzz::text(data, size), "fuzz.tact", options);
}
