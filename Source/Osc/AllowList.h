#pragma once
// Who may talk to a listening socket (docs/SECURITY.md): the address a listener binds (loopback
// unless told otherwise) and an allow-list of networks, `ADDR[/BITS],…` in IPv4 or IPv6
// (`play --control-bind`, `--control-allow`, the app's stage-control settings). Plain values and
// socket addresses only: the sockets themselves are in Osc/OscIo.h and Live/Stage/StageControl.h.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

struct sockaddr;

namespace armadillo::osc {

/// The address a listener binds by default: loopback, nobody else on the network reaches it.
inline constexpr const char* kLoopbackAddress = "127.0.0.1";

/// True when `text` is a numeric IPv4 or IPv6 address ("127.0.0.1", "0.0.0.0", "::1", "::").
bool isIpAddress(const std::string& text);
/// True for 127.0.0.0/8 and ::1 (and ::ffff:127.x.y.z).
bool isLoopbackAddress(const std::string& text);

/// A list of networks a sender's address must fall in. Empty: every sender that reaches the
/// socket (the bind address is then the only fence).
class AllowList {
public:
    /// "ADDR[/BITS],ADDR[/BITS],…": IPv4 (BITS 0..32, default 32) or IPv6 (0..128, default 128),
    /// spaces around items allowed. Throws std::invalid_argument saying which item is wrong and
    /// why ("'10.0.0.300' is not an IPv4 or IPv6 address"); an empty text is an error too.
    static AllowList parse(const std::string& text);

    bool empty() const noexcept { return nets_.empty(); }
    /// Whether `address` (AF_INET, or AF_INET6 with IPv4-mapped addresses taken as IPv4) is in
    /// one of the networks; an empty list allows everyone. No allocation.
    bool allows(const sockaddr* address) const noexcept;
    /// The list as given, normalised ("127.0.0.2/32, 10.0.0.0/24").
    std::string describe() const;

private:
    struct Net {
        int family = 0;                      // AF_INET or AF_INET6
        std::array<std::uint8_t, 16> bytes {};
        int bits = 0;
    };
    std::vector<Net> nets_;
};

/// A sender's address in words, without the port ("127.0.0.1", "fe80::1"); IPv4-mapped IPv6
/// addresses are shown as IPv4.
std::string addressName(const sockaddr* address);

} // namespace armadillo::osc
