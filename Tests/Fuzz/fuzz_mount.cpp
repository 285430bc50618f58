// Mount JSON (Link/Mount.h parseMount: a sensor's axes → the forearm's).
#include "FuzzTarget.h"
#include "Link/Mount.h"

ARMADILLO_FUZZ_TARGET(mount)
{
    (void)armadillo::link::parseMount(armadillo::fuzz::text(data, size), "fuzz.json");
}
