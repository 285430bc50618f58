// Meta Haptics Studio `.haptic` files imported as a tactile score (importMetaHaptic).
#include "Formats/ScoreImport.h"
#include "FuzzTarget.h"

ARMADILLO_FUZZ_TARGET(haptic)
{
    (void)armadillo::formats::importMetaHaptic(armadillo::fuzz::text(data, size), "fuzz.haptic", {});
}
