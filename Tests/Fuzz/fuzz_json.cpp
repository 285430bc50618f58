// The generic JSON reader (Core/Json.h) every JSON format goes through, and its writer's escaping.
#include "Core/Json.h"
#include "FuzzTarget.h"

ARMADILLO_FUZZ_TARGET(json)
{
    const auto text = armadillo::fuzz::text(data, size);
    const armadillo::core::JsonValue v = armadillo::core::parseJson(text, "fuzz.json");
    if (v.kind == armadillo::core::JsonValue::Kind::Object) (void)v.find("a");
    std::string out;
    armadillo::core::appendJsonString(out, text);   // any bytes: escaped, never cut short
}
