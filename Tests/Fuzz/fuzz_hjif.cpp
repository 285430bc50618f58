// MPEG haptics `.hjif` files (ISO/IEC 23090-31, issue 50) imported as a tactile score
// (importHjif): the JSON, the perceptions, channels, bands, effects, keyframes and the library
// references, evaluated within the importer's budget.
#include "Formats/ScoreImport.h"
#include "FuzzTarget.h"

ARMADILLO_FUZZ_TARGET(hjif)
{
    armadillo::formats::HapticImportOptions options;
    (void)armadillo::formats::importHjif(armadillo::fuzz::text(data, size), "fuzz.hjif", options);
}
