// The reader profile JSON (Access/ReaderProfile.h), read back after being written.
#include "Access/ReaderProfile.h"
#include "FuzzTarget.h"

ARMADILLO_FUZZ_TARGET(reader_profile)
{
    using namespace armadillo::access;
    const ReaderProfile p = parseReaderProfile(armadillo::fuzz::text(data, size), "fuzz.json");
    (void)parseReaderProfile(readerProfileToJson(p), "fuzz.json (written back)");
}
