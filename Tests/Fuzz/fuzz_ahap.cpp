// Apple AHAP haptic files imported as a tactile score (Formats/ScoreImport.h importAhap).
#include "Formats/ScoreImport.h"
#include "FuzzTarget.h"

ARMADILLO_FUZZ_TARGET(ahap)
{
    (void)armadillo::formats::importAhap(armadillo::fuzz::text(data, size), "fuzz.ahap", {});
}
