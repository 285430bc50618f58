#include "Osc/AllowList.h"
#include <arpa/inet.h>
#include <charconv>
#include <cstring>
#include <netinet/in.h>
#include <stdexcept>
#include <sys/socket.h>

namespace armadillo::osc {

namespace {

std::string trimmed(const std::string& s)
{
    const auto a = s.find_first_not_of(" \t");
    if (a == std::string::npos) return {};
    const auto b = s.find_last_not_of(" \t");
    return s.substr(a, b - a + 1);
}

/// The 4 (AF_INET) or 16 (AF_INET6) bytes of `address`, IPv4-mapped IPv6 as IPv4. 0: neither.
int addressBytes(const sockaddr* address, std::uint8_t out[16]) noexcept
{
    if (address == nullptr) return 0;
    if (address->sa_family == AF_INET) {
        std::memcpy(out, &reinterpret_cast<const sockaddr_in*>(address)->sin_addr, 4);
        return AF_INET;
    }
    if (address->sa_family == AF_INET6) {
        const in6_addr& a = reinterpret_cast<const sockaddr_in6*>(address)->sin6_addr;
        if (IN6_IS_ADDR_V4MAPPED(&a)) {
            std::memcpy(out, a.s6_addr + 12, 4);
            return AF_INET;
        }
        std::memcpy(out, a.s6_addr, 16);
        return AF_INET6;
    }
    return 0;
}

bool prefixMatches(const std::uint8_t* a, const std::uint8_t* b, int bits) noexcept
{
    const int whole = bits / 8, rest = bits % 8;
    if (std::memcmp(a, b, static_cast<std::size_t>(whole)) != 0) return false;
    if (rest == 0) return true;
    const std::uint8_t mask = static_cast<std::uint8_t>(0xFF << (8 - rest));
    return (a[whole] & mask) == (b[whole] & mask);
}

} // namespace

bool isIpAddress(const std::string& text)
{
    unsigned char buf[16];
    return ::inet_pton(AF_INET, text.c_str(), buf) == 1 || ::inet_pton(AF_INET6, text.c_str(), buf) == 1;
}

bool isLoopbackAddress(const std::string& text)
{
    in_addr a4 {};
    in6_addr a6 {};
    if (::inet_pton(AF_INET, text.c_str(), &a4) == 1) return (ntohl(a4.s_addr) >> 24) == 127;
    if (::inet_pton(AF_INET6, text.c_str(), &a6) == 1)
        return IN6_IS_ADDR_LOOPBACK(&a6) || (IN6_IS_ADDR_V4MAPPED(&a6) && a6.s6_addr[12] == 127);
    return false;
}

AllowList AllowList::parse(const std::string& text)
{
    AllowList list;
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t comma = std::min(text.find(',', start), text.size());
        const std::string item = trimmed(text.substr(start, comma - start));
        start = comma + 1;
        if (item.empty()) throw std::invalid_argument("an empty entry (give ADDR[/BITS],… such as 127.0.0.1 or 192.168.1.0/24)");
        const auto slash = item.find('/');
        const std::string address = item.substr(0, slash);
        Net net;
        if (::inet_pton(AF_INET, address.c_str(), net.bytes.data()) == 1) {
            net.family = AF_INET;
            net.bits = 32;
        } else if (::inet_pton(AF_INET6, address.c_str(), net.bytes.data()) == 1) {
            net.family = AF_INET6;
            net.bits = 128;
            if (IN6_IS_ADDR_V4MAPPED(reinterpret_cast<const in6_addr*>(net.bytes.data()))) {   // ::ffff:a.b.c.d is IPv4
                std::memmove(net.bytes.data(), net.bytes.data() + 12, 4);
                net.family = AF_INET;
                net.bits = 32;
            }
        } else {
            throw std::invalid_argument("'" + address + "' is not an IPv4 or IPv6 address");
        }
        if (slash != std::string::npos) {
            const std::string b = item.substr(slash + 1);
            const int most = net.family == AF_INET ? 32 : 128;
            int bits = -1;
            const auto [end, ec] = std::from_chars(b.data(), b.data() + b.size(), bits);
            if (b.empty() || ec != std::errc() || end != b.data() + b.size() || bits < 0 || bits > most)
                throw std::invalid_argument("'" + item + "': the prefix length after / must be a whole number 0.." + std::to_string(most));
            net.bits = bits;
        }
        list.nets_.push_back(net);
        if (comma == text.size()) break;
    }
    return list;
}

bool AllowList::allows(const sockaddr* address) const noexcept
{
    if (nets_.empty()) return true;
    std::uint8_t bytes[16];
    const int family = addressBytes(address, bytes);
    for (const Net& n : nets_)
        if (n.family == family && prefixMatches(bytes, n.bytes.data(), n.bits)) return true;
    return false;
}

std::string AllowList::describe() const
{
    std::string s;
    for (const Net& n : nets_) {
        char text[INET6_ADDRSTRLEN] {};
        ::inet_ntop(n.family, n.bytes.data(), text, sizeof text);
        s += (s.empty() ? "" : ", ") + std::string(text) + "/" + std::to_string(n.bits);
    }
    return s;
}

std::string addressName(const sockaddr* address)
{
    std::uint8_t bytes[16];
    const int family = addressBytes(address, bytes);
    if (family == 0) return "?";
    char text[INET6_ADDRSTRLEN] {};
    ::inet_ntop(family, bytes, text, sizeof text);
    return text;
}

} // namespace armadillo::osc
