#include "Device/OscIo.h"
#include "Core/Errors.h"
#include "Core/Pose.h"
#include <arpa/inet.h>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <stdexcept>
#include <sys/socket.h>
#include <unistd.h>
#include <vector>

namespace armadillo::device {

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

// --- OscSender ---------------------------------------------------------------------------------

OscSender::OscSender(const HostPort& destination)
{
    addrinfo hints {};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_DGRAM;
    addrinfo* res = nullptr;
    const std::string port = std::to_string(destination.port);
    const int r = ::getaddrinfo(destination.host.c_str(), port.c_str(), &hints, &res);
    if (r != 0 || !res) throw IoError("OSC out: cannot resolve '" + destination.host + "': " + ::gai_strerror(r));
    fd_ = ::socket(res->ai_family, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd_ < 0 || res->ai_addrlen > sizeof addr_) {
        const int e = errno;
        ::freeaddrinfo(res);
        throw IoError(std::string("OSC out: cannot create a UDP socket: ") + std::strerror(e));
    }
    std::memcpy(addr_, res->ai_addr, res->ai_addrlen);
    addrLen_ = static_cast<unsigned>(res->ai_addrlen);
    ::freeaddrinfo(res);
}

OscSender::~OscSender()
{
    if (fd_ >= 0) ::close(fd_);
}

bool OscSender::send(std::string_view address, const OscArg* args, std::size_t count) noexcept
{
    std::uint8_t buffer[512];
    const std::size_t n = encodeOscMessage(address, args, count, buffer, sizeof buffer);
    if (n == 0 || ::sendto(fd_, buffer, n, MSG_DONTWAIT | MSG_NOSIGNAL, reinterpret_cast<const sockaddr*>(addr_), addrLen_) != static_cast<ssize_t>(n)) {
        dropped_.fetch_add(1, std::memory_order_relaxed);
        return false;
    }
    sent_.fetch_add(1, std::memory_order_relaxed);
    return true;
}

bool OscSender::sendOrientation(const Eigen::Quaterniond& q) noexcept
{
    const OscArg a[] = {OscArg::float32(float(q.w())), OscArg::float32(float(q.x())), OscArg::float32(float(q.y())), OscArg::float32(float(q.z()))};
    return send("/armadillo/orientation", a, 4);
}

bool OscSender::sendPose(const Pose& p) noexcept
{
    const OscArg a[] = {OscArg::float32(float(p.elevationDeg)), OscArg::float32(float(p.azimuthDeg)), OscArg::float32(float(p.rollDeg))};
    return send("/armadillo/pose", a, 3);
}

bool OscSender::sendGyro(const Eigen::Vector3d& g) noexcept
{
    const OscArg a[] = {OscArg::float32(float(g.x())), OscArg::float32(float(g.y())), OscArg::float32(float(g.z()))};
    return send("/armadillo/gyro", a, 3);
}

bool OscSender::sendMotors(const MotorLevels& levels, int motorCount) noexcept
{
    OscArg a[kMaxMotors];
    const int n = std::clamp(motorCount, 1, kMaxMotors);
    for (int i = 0; i < n; ++i) a[i] = OscArg::int32(levels[static_cast<std::size_t>(i)]);
    return send("/armadillo/motors", a, static_cast<std::size_t>(n));
}

bool OscSender::sendGesture(const char* name) noexcept
{
    const OscArg a[] = {OscArg::string(name ? name : "")};
    return send("/armadillo/gesture", a, 1);
}

// --- OscReceiver -------------------------------------------------------------------------------

OscReceiver::OscReceiver(int port, ImuHandler onImu, OrientationHandler onOrientation, const OscInputOptions& options)
    : onImu_(std::move(onImu)), onOrientation_(std::move(onOrientation)), merger_(options)
{
    merger_.setSinks(
        [](void* c, const ImuSample& s) {
            auto* self = static_cast<OscReceiver*>(c);
            if (self->onImu_) self->onImu_(s);
        },
        [](void* c, double t, const Eigen::Quaterniond& q) {
            auto* self = static_cast<OscReceiver*>(c);
            if (self->onOrientation_) self->onOrientation_(t, q);
        },
        this);
    if (port < 0 || port > 65535) throw IoError("OSC in: port " + std::to_string(port) + " is outside 0..65535");
    // One IPv6 socket that also takes IPv4 (as v4-mapped addresses), so phones and trackers on
    // either protocol reach the same port, as the sender already resolves both; plain IPv4 when
    // the machine has no IPv6.
    const auto bindOrThrow = [this, port](const sockaddr* address, socklen_t size) {
        if (::bind(fd_, address, size) == 0) return;
        const int e = errno;
        ::close(fd_);
        fd_ = -1;
        throw IoError("OSC in: cannot listen on UDP port " + std::to_string(port) + ": " + std::strerror(e));
    };
    fd_ = ::socket(AF_INET6, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (fd_ >= 0) {
        const int off = 0;
        ::setsockopt(fd_, IPPROTO_IPV6, IPV6_V6ONLY, &off, sizeof off);
        sockaddr_in6 a {};
        a.sin6_family = AF_INET6;
        a.sin6_addr = in6addr_any;
        a.sin6_port = htons(static_cast<std::uint16_t>(port));
        bindOrThrow(reinterpret_cast<sockaddr*>(&a), sizeof a);
    } else {
        fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
        if (fd_ < 0) throw IoError(std::string("OSC in: cannot create a UDP socket: ") + std::strerror(errno));
        sockaddr_in a {};
        a.sin_family = AF_INET;
        a.sin_addr.s_addr = htonl(INADDR_ANY);
        a.sin_port = htons(static_cast<std::uint16_t>(port));
        bindOrThrow(reinterpret_cast<sockaddr*>(&a), sizeof a);
    }
    sockaddr_storage bound {};
    socklen_t len = sizeof bound;
    ::getsockname(fd_, reinterpret_cast<sockaddr*>(&bound), &len);
    port_ = bound.ss_family == AF_INET6 ? ntohs(reinterpret_cast<sockaddr_in6*>(&bound)->sin6_port)
                                        : ntohs(reinterpret_cast<sockaddr_in*>(&bound)->sin_port);
    start_ = std::chrono::steady_clock::now();
}

OscReceiver::~OscReceiver()
{
    stop();
    if (fd_ >= 0) ::close(fd_);
}

void OscReceiver::start()
{
    if (thread_.joinable()) return;
    stop_.store(false);
    thread_ = std::thread([this] { run(); });
}

void OscReceiver::stop()
{
    stop_.store(true);
    if (thread_.joinable()) thread_.join();
}

void OscReceiver::handleDatagram(const std::uint8_t* data, std::size_t size, double t, std::uint64_t senderKey, const char* senderName)
{
    merger_.handleDatagram(data, size, t, senderKey, senderName);
}

void OscReceiver::run()
{
    std::vector<std::uint8_t> buffer(65536);
    while (!stop_.load(std::memory_order_relaxed)) {
        pollfd p {fd_, POLLIN, 0};
        const int ready = ::poll(&p, 1, 20);
        // Held readings of a sender at rest (Sensors2OSC sends nothing unchanged) are sampled here.
        merger_.tick(std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count());
        if (ready <= 0) continue;
        sockaddr_storage from {};
        socklen_t fromLen = sizeof from;
        const ssize_t n = ::recvfrom(fd_, buffer.data(), buffer.size(), MSG_DONTWAIT, reinterpret_cast<sockaddr*>(&from), &fromLen);
        if (n <= 0) continue;
        // Arrival time on the monotonic clock: what "immediately" bundles and bare messages are stamped with.
        const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
        char name[64];
        std::uint64_t key = 0;
        const unsigned char* v6 = nullptr;
        std::uint16_t port = 0;
        std::uint32_t ip = 0;
        bool v4 = false;
        if (from.ss_family == AF_INET6) {
            const auto* a = reinterpret_cast<const sockaddr_in6*>(&from);
            v6 = a->sin6_addr.s6_addr;
            port = ntohs(a->sin6_port);
            if (IN6_IS_ADDR_V4MAPPED(&a->sin6_addr)) {   // an IPv4 sender: named and keyed as before
                ip = (std::uint32_t(v6[12]) << 24) | (std::uint32_t(v6[13]) << 16) | (std::uint32_t(v6[14]) << 8) | v6[15];
                v4 = true;
            }
        } else {
            const auto* a = reinterpret_cast<const sockaddr_in*>(&from);
            ip = ntohl(a->sin_addr.s_addr);
            port = ntohs(a->sin_port);
            v4 = true;
        }
        if (v4) {
            std::snprintf(name, sizeof name, "%u.%u.%u.%u:%u", ip >> 24, (ip >> 16) & 255u, (ip >> 8) & 255u, ip & 255u, unsigned(port));
            key = (std::uint64_t(ip) << 16 | port) + 1;
        } else {
            char text[INET6_ADDRSTRLEN] = "";
            ::inet_ntop(AF_INET6, v6, text, sizeof text);
            std::snprintf(name, sizeof name, "[%s]:%u", text, unsigned(port));
            key = 1469598103934665603ull;   // FNV-1a over address and port, top bit set: never an IPv4 key (< 2^48)
            for (int i = 0; i < 16; ++i) key = (key ^ v6[i]) * 1099511628211ull;
            key = ((key ^ port) * 1099511628211ull) | (std::uint64_t(1) << 63);
        }
        handleDatagram(buffer.data(), static_cast<std::size_t>(n), t, key, name);
    }
}

} // namespace armadillo::device
