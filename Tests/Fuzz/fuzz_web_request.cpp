// The web page's request checks (Web/WebRequest.h): what a browser or anyone on the network sends
// the page's server — the bodies of its two state changes, the path, Host, Origin and Cookie
// headers — before anything reaches the instrument. The input is split at its first two NULs
// into a header value, a second one and a body.
#include "FuzzTarget.h"
#include "Web/WebRequest.h"
#include <string_view>
#include <vector>

ARMADILLO_FUZZ_TARGET(web_request)
{
    using namespace armadillo::web;
    const std::string_view all(reinterpret_cast<const char*>(data), size);
    const std::size_t a = all.find('\0');
    const std::string_view first = all.substr(0, a);
    const std::string_view rest = a == std::string_view::npos ? std::string_view {} : all.substr(a + 1);
    const std::size_t b = rest.find('\0');
    const std::string_view second = rest.substr(0, b);
    const std::string_view body = b == std::string_view::npos ? rest : rest.substr(b + 1);

    (void) parseStageCommand(body);
    (void) parseProcedureCommand(body);
    (void) parseTouchCommand(body);
    (void) parseSceneChoice(body);
    if (const auto p = parseParamRequest(body)) {
        if (p->id.empty() || p->id.size() > 64) __builtin_trap();   // the bounds parseParamRequest promises
    }
    (void) pageFile(first);
    static const std::vector<std::string> hosts = allowedHosts("", 8080);
    (void) hostAllowed(first, hosts);
    (void) originAllowed(second, first, hosts);
    (void) cookieValue(second, "armadillo_token");
    (void) tokenEquals(first, "0123456789abcdef0123456789abcdef");
    static ClientLimiter limiter;
    (void) limiter.admit(std::string(first.substr(0, 64)), static_cast<double>(size) * 0.001);
}
