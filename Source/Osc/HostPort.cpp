#include "Osc/HostPort.h"
#include <charconv>
#include <stdexcept>

namespace armadillo::osc {

HostPort parseHostPort(const std::string& text)
{
    HostPort hp;
    std::string portText;
    if (!text.empty() && text[0] == '[') {
        const auto close = text.find(']');
        if (close == std::string::npos || close + 1 >= text.size() || text[close + 1] != ':')
            throw std::invalid_argument("'" + text + "' is not [IPv6]:PORT");
        hp.host = text.substr(1, close - 1);
        portText = text.substr(close + 2);
    } else if (const auto colon = text.rfind(':'); colon != std::string::npos) {
        if (text.find(':') != colon) throw std::invalid_argument("'" + text + "': write IPv6 addresses as [ADDR]:PORT");
        hp.host = text.substr(0, colon);
        portText = text.substr(colon + 1);
    } else {
        portText = text;
    }
    if (hp.host.empty()) hp.host = "127.0.0.1";
    int port = 0;
    const auto [end, ec] = std::from_chars(portText.data(), portText.data() + portText.size(), port);
    if (portText.empty() || ec != std::errc() || end != portText.data() + portText.size() || port < 1 || port > 65535)
        throw std::invalid_argument("'" + text + "': the port must be a number 1..65535");
    hp.port = port;
    return hp;
}

} // namespace armadillo::osc
