// Route JSON for walking navigation (Navigation/Route.h parseRouteJson).
#include "FuzzTarget.h"
#include "Navigation/Route.h"

ARMADILLO_FUZZ_TARGET(route_json)
{
    const auto route = armadillo::navigation::parseRouteJson(armadillo::fuzz::text(data, size), "fuzz.json");
    (void)route.lengthM();
}
