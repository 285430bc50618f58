#include "Osc/OscIo.h"
#include "Core/Errors.h"
#include "Core/Pose.h"
#include "Core/ThreadPriority.h"
#include "Link/LinkPort.h"
#include "Osc/OscStream.h"
#include "Osc/Slip.h"
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

namespace armadillo::osc {

// --- OscSender ---------------------------------------------------------------------------------

OscSender::OscSender(const HostPort& destination)
{
    addrinfo hints {};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_DGRAM;
    addrinfo* res = nullptr;
    const std::string port = std::to_string(destination.port);
    const int r = ::getaddrinfo(destination.host.c_str(), port.c_str(), &hints, &res);
    if (r != 0 || !res) throw core::IoError("OSC out: cannot resolve '" + destination.host + "': " + ::gai_strerror(r));
    fd_ = ::socket(res->ai_family, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd_ < 0 || res->ai_addrlen > sizeof addr_) {
        const int e = errno;
        ::freeaddrinfo(res);
        throw core::IoError(std::string("OSC out: cannot create a UDP socket: ") + std::strerror(e));
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

bool OscSender::sendPacket(const std::uint8_t* data, std::size_t size) noexcept
{
    if (data == nullptr || size == 0 ||
        ::sendto(fd_, data, size, MSG_DONTWAIT | MSG_NOSIGNAL, reinterpret_cast<const sockaddr*>(addr_), addrLen_) != static_cast<ssize_t>(size)) {
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

bool OscSender::sendPose(const core::Pose& p) noexcept
{
    const OscArg a[] = {OscArg::float32(float(p.elevationDeg)), OscArg::float32(float(p.azimuthDeg)), OscArg::float32(float(p.rollDeg))};
    return send("/armadillo/pose", a, 3);
}

bool OscSender::sendGyro(const Eigen::Vector3d& g) noexcept
{
    const OscArg a[] = {OscArg::float32(float(g.x())), OscArg::float32(float(g.y())), OscArg::float32(float(g.z()))};
    return send("/armadillo/gyro", a, 3);
}

bool OscSender::sendMotors(const core::MotorLevels& levels, int motorCount) noexcept
{
    OscArg a[core::kMaxMotors];
    const int n = std::clamp(motorCount, 1, core::kMaxMotors);
    for (int i = 0; i < n; ++i) a[i] = OscArg::int32(levels[static_cast<std::size_t>(i)]);
    return send("/armadillo/motors", a, static_cast<std::size_t>(n));
}

bool OscSender::sendGesture(const char* name) noexcept
{
    const OscArg a[] = {OscArg::string(name ? name : "")};
    return send("/armadillo/gesture", a, 1);
}

/// The port a bound socket got (the one asked for, or the free one given for port 0).
static int localPort(int fd) noexcept
{
    sockaddr_storage bound {};
    socklen_t len = sizeof bound;
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&bound), &len);
    return bound.ss_family == AF_INET6 ? ntohs(reinterpret_cast<sockaddr_in6*>(&bound)->sin6_port)
                                       : ntohs(reinterpret_cast<sockaddr_in*>(&bound)->sin_port);
}

int bindUdpAnyInterface(int port, const std::string& who, int& boundPort)
{
    if (port < 0 || port > 65535) throw core::IoError(who + ": port " + std::to_string(port) + " is outside 0..65535");
    int fd = -1;
    const auto bindOrThrow = [&fd, &who, port](const sockaddr* address, socklen_t size) {
        if (::bind(fd, address, size) == 0) return;
        const int e = errno;
        ::close(fd);
        throw core::IoError(who + ": cannot listen on UDP port " + std::to_string(port) + ": " + std::strerror(e));
    };
    fd = ::socket(AF_INET6, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (fd >= 0) {
        const int off = 0;
        ::setsockopt(fd, IPPROTO_IPV6, IPV6_V6ONLY, &off, sizeof off);
        sockaddr_in6 a {};
        a.sin6_family = AF_INET6;
        a.sin6_addr = in6addr_any;
        a.sin6_port = htons(static_cast<std::uint16_t>(port));
        bindOrThrow(reinterpret_cast<sockaddr*>(&a), sizeof a);
    } else {
        fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
        if (fd < 0) throw core::IoError(who + ": cannot create a UDP socket: " + std::strerror(errno));
        sockaddr_in a {};
        a.sin_family = AF_INET;
        a.sin_addr.s_addr = htonl(INADDR_ANY);
        a.sin_port = htons(static_cast<std::uint16_t>(port));
        bindOrThrow(reinterpret_cast<sockaddr*>(&a), sizeof a);
    }
    boundPort = localPort(fd);
    return fd;
}

int bindUdp(const std::string& address, int port, const std::string& who, int& boundPort)
{
    if (address.empty()) return bindUdpAnyInterface(port, who, boundPort);
    if (port < 0 || port > 65535) throw core::IoError(who + ": port " + std::to_string(port) + " is outside 0..65535");
    sockaddr_in a4 {};
    sockaddr_in6 a6 {};
    const bool v4 = ::inet_pton(AF_INET, address.c_str(), &a4.sin_addr) == 1;
    if (!v4 && ::inet_pton(AF_INET6, address.c_str(), &a6.sin6_addr) != 1)
        throw core::IoError(who + ": '" + address + "' is not an IPv4 or IPv6 address");
    const int fd = ::socket(v4 ? AF_INET : AF_INET6, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (fd < 0) throw core::IoError(who + ": cannot create a UDP socket: " + std::strerror(errno));
    int r = -1;
    if (v4) {
        a4.sin_family = AF_INET;
        a4.sin_port = htons(static_cast<std::uint16_t>(port));
        r = ::bind(fd, reinterpret_cast<sockaddr*>(&a4), sizeof a4);
    } else {
        const int off = 0;   // "::" takes IPv4 too, as bindUdpAnyInterface does
        ::setsockopt(fd, IPPROTO_IPV6, IPV6_V6ONLY, &off, sizeof off);
        a6.sin6_family = AF_INET6;
        a6.sin6_port = htons(static_cast<std::uint16_t>(port));
        r = ::bind(fd, reinterpret_cast<sockaddr*>(&a6), sizeof a6);
    }
    if (r != 0) {
        const int e = errno;
        ::close(fd);
        throw core::IoError(who + ": cannot listen on UDP " + address + " port " + std::to_string(port) + ": " + std::strerror(e));
    }
    boundPort = localPort(fd);
    return fd;
}

// --- OscReceiver -------------------------------------------------------------------------------

OscReceiver::OscReceiver(int port, ImuHandler onImu, OrientationHandler onOrientation, const OscInputOptions& options)
    : onImu_(std::move(onImu)), onOrientation_(std::move(onOrientation)), merger_(options), realtimePriority_(options.realtimePriority)
{
    merger_.setSinks(
        [](void* c, const core::ImuSample& s) {
            auto* self = static_cast<OscReceiver*>(c);
            if (self->onImu_) self->onImu_(s);
        },
        [](void* c, double t, const Eigen::Quaterniond& q) {
            auto* self = static_cast<OscReceiver*>(c);
            if (self->onOrientation_) self->onOrientation_(t, q);
        },
        this);
    if (port < 0 || port > 65535) throw core::IoError("OSC in: port " + std::to_string(port) + " is outside 0..65535");
    // Phones and trackers on either protocol reach the same port, as the sender already resolves both.
    fd_ = bindUdpAnyInterface(port, "OSC in", port_);
    sockaddr_storage bound {};
    socklen_t len = sizeof bound;
    ::getsockname(fd_, reinterpret_cast<sockaddr*>(&bound), &len);
    // The same port number on TCP, for ZIG SIM's TCP option (same family as the UDP socket).
    const int family = bound.ss_family;
    tcpFd_ = ::socket(family, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (tcpFd_ >= 0) {
        const int on = 1, off = 0;
        ::setsockopt(tcpFd_, SOL_SOCKET, SO_REUSEADDR, &on, sizeof on);
        int r = -1;
        if (family == AF_INET6) {
            ::setsockopt(tcpFd_, IPPROTO_IPV6, IPV6_V6ONLY, &off, sizeof off);
            sockaddr_in6 a {};
            a.sin6_family = AF_INET6;
            a.sin6_addr = in6addr_any;
            a.sin6_port = htons(static_cast<std::uint16_t>(port_));
            r = ::bind(tcpFd_, reinterpret_cast<sockaddr*>(&a), sizeof a);
        } else {
            sockaddr_in a {};
            a.sin_family = AF_INET;
            a.sin_addr.s_addr = htonl(INADDR_ANY);
            a.sin_port = htons(static_cast<std::uint16_t>(port_));
            r = ::bind(tcpFd_, reinterpret_cast<sockaddr*>(&a), sizeof a);
        }
        if (r != 0 || ::listen(tcpFd_, 4) != 0) {
            tcpError_ = "TCP port " + std::to_string(port_) + ": " + std::strerror(errno);
            ::close(tcpFd_);
            tcpFd_ = -1;
        }
    } else {
        tcpError_ = std::string("no TCP socket: ") + std::strerror(errno);
    }
    start_ = std::chrono::steady_clock::now();
}

OscReceiver::OscReceiver(const OscSerialSource& serial, ImuHandler onImu, OrientationHandler onOrientation, const OscInputOptions& options)
    : serial_(serial), onImu_(std::move(onImu)), onOrientation_(std::move(onOrientation)), merger_(options),
      realtimePriority_(options.realtimePriority)
{
    merger_.setSinks(
        [](void* c, const core::ImuSample& s) {
            auto* self = static_cast<OscReceiver*>(c);
            if (self->onImu_) self->onImu_(s);
        },
        [](void* c, double t, const Eigen::Quaterniond& q) {
            auto* self = static_cast<OscReceiver*>(c);
            if (self->onOrientation_) self->onOrientation_(t, q);
        },
        this);
    // The same serial code as the thesis board (libserialport, or termios for ptys and rfcomm).
    serialPort_ = std::make_unique<link::SerialPort>(serial_.path, serial_.baud);
    serialPort_->open();   // IoError naming the port
    start_ = std::chrono::steady_clock::now();
}

std::string OscReceiver::serialError() const
{
    while (serialErrorLock_.exchange(true, std::memory_order_acquire)) {}
    std::string e = serialError_;
    serialErrorLock_.store(false, std::memory_order_release);
    return e;
}

double OscReceiver::now() const noexcept { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

OscReceiver::~OscReceiver()
{
    stop();
    if (fd_ >= 0) ::close(fd_);
    if (tcpFd_ >= 0) ::close(tcpFd_);
    if (serialPort_) serialPort_->close();
}

void OscReceiver::start()
{
    if (thread_.joinable()) return;
    stop_.store(false);
    thread_ = std::thread([this] {
        if (realtimePriority_ > 0) core::requestRealtimePriority(realtimePriority_);
        serialPort_ ? runSerial() : run();
    });
}

void OscReceiver::runSerial()
{
    std::vector<std::uint8_t> buffer(4096);
    SlipDecoder slip(65536);
    std::uint64_t key = 1469598103934665603ull;
    for (const char c : serial_.path) key = (key ^ static_cast<unsigned char>(c)) * 1099511628211ull;
    const char* name = serial_.path.c_str();
    double retryAt = 0.0;
    auto setError = [this](const std::string& e) {
        while (serialErrorLock_.exchange(true, std::memory_order_acquire)) {}
        serialError_ = e;
        serialErrorLock_.store(false, std::memory_order_release);
    };
    while (!stop_.load(std::memory_order_relaxed)) {
        merger_.tick(now());
        if (!serialPort_->isOpen()) {   // unplugged: try again twice a second
            if (now() < retryAt) {
                std::this_thread::sleep_for(std::chrono::milliseconds(20));
                continue;
            }
            try {
                serialPort_->open();
                slip = SlipDecoder(65536);
                setError("");
            } catch (const std::exception& e) {
                setError(e.what());
                retryAt = now() + 0.5;
                continue;
            }
        }
        std::size_t n = 0;
        try {
            n = serialPort_->read(buffer.data(), buffer.size(), 0.02);
        } catch (const std::exception& e) {
            setError(e.what());
            serialPort_->close();
            retryAt = now() + 0.5;
            continue;
        }
        if (n == 0) continue;
        const double t = now();
        slip.feed(buffer.data(), n, [&](const std::uint8_t* p, std::size_t size) { merger_.handleDatagram(p, size, t, key, name); });
    }
}

void OscReceiver::stop()
{
    stop_.store(true);
    if (thread_.joinable()) thread_.join();
}

void OscReceiver::handleDatagram(const std::uint8_t* data, std::size_t size, double t, std::uint64_t senderKey, const char* senderName)
{
    if (tap_) tap_(data, size);
    merger_.handleDatagram(data, size, t, senderKey, senderName);
}

struct OscReceiver::TcpClient {
    int fd = -1;
    std::uint64_t key = 0;
    char name[64] {};
    std::unique_ptr<OscStreamSplitter> splitter;
};

namespace {

/// A sender's name ("a.b.c.d:port" or "[v6]:port") and key (IPv4 keys stay below 2^48, IPv6 keys have the top bit).
void senderOf(const sockaddr_storage& from, char (&name)[64], std::uint64_t& key)
{
    const unsigned char* v6 = nullptr;
    std::uint16_t port = 0;
    std::uint32_t ip = 0;
    bool v4 = false;
    if (from.ss_family == AF_INET6) {
        const auto* a = reinterpret_cast<const sockaddr_in6*>(&from);
        v6 = a->sin6_addr.s6_addr;
        port = ntohs(a->sin6_port);
        if (IN6_IS_ADDR_V4MAPPED(&a->sin6_addr)) {   // an IPv4 sender: named and keyed as such
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
}

} // namespace

void OscReceiver::run()
{
    constexpr std::size_t kMaxClients = 4;
    std::vector<std::uint8_t> buffer(65536);
    std::vector<TcpClient> clients(kMaxClients);
    for (auto& c : clients) c.splitter = std::make_unique<OscStreamSplitter>();
    struct Unit {
        OscReceiver* self;
        double t;
        const TcpClient* client;
    };
    while (!stop_.load(std::memory_order_relaxed)) {
        pollfd p[2 + kMaxClients];
        nfds_t count = 0;
        p[count++] = {fd_, POLLIN, 0};
        if (tcpFd_ >= 0) p[count++] = {tcpFd_, POLLIN, 0};
        const nfds_t firstClient = count;
        TcpClient* polled[kMaxClients] {};
        for (auto& c : clients)
            if (c.fd >= 0) {
                polled[count - firstClient] = &c;
                p[count++] = {c.fd, POLLIN, 0};
            }
        const int ready = ::poll(p, count, 20);
        // Held readings of a sender at rest (Sensors2OSC sends nothing unchanged) are sampled here.
        merger_.tick(now());
        if (ready <= 0) continue;
        if (p[0].revents & POLLIN) {
            sockaddr_storage from {};
            socklen_t fromLen = sizeof from;
            const ssize_t n = ::recvfrom(fd_, buffer.data(), buffer.size(), MSG_DONTWAIT, reinterpret_cast<sockaddr*>(&from), &fromLen);
            if (n > 0) {
                // Arrival time on the monotonic clock: what "immediately" bundles and bare messages are stamped with.
                const double t = now();
                char name[64];
                std::uint64_t key = 0;
                senderOf(from, name, key);
                handleDatagram(buffer.data(), static_cast<std::size_t>(n), t, key, name);
            }
        }
        if (tcpFd_ >= 0 && (p[1].revents & POLLIN)) {
            sockaddr_storage from {};
            socklen_t fromLen = sizeof from;
            const int c = ::accept4(tcpFd_, reinterpret_cast<sockaddr*>(&from), &fromLen, SOCK_NONBLOCK | SOCK_CLOEXEC);
            if (c >= 0) {
                TcpClient* slot = nullptr;
                for (auto& x : clients)
                    if (x.fd < 0) slot = &x;
                if (!slot) {
                    ::close(c);   // more senders than ARMadillo follows: refused
                } else {
                    slot->fd = c;
                    senderOf(from, slot->name, slot->key);
                    slot->splitter->reset();
                    tcpAccepted_.fetch_add(1, std::memory_order_relaxed);
                }
            }
        }
        for (nfds_t i = firstClient; i < count; ++i) {
            TcpClient& c = *polled[i - firstClient];
            if (!(p[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
            const ssize_t n = ::recv(c.fd, buffer.data(), buffer.size(), MSG_DONTWAIT);
            if (n <= 0) {
                if (n == 0 || (errno != EAGAIN && errno != EINTR)) {   // closed by the sender
                    ::close(c.fd);
                    c.fd = -1;
                }
                continue;
            }
            Unit u {this, now(), &c};
            c.splitter->feed(
                buffer.data(), static_cast<std::size_t>(n),
                [](void* x, const std::uint8_t* unit, std::size_t size) {
                    auto* w = static_cast<Unit*>(x);
                    w->self->handleDatagram(unit, size, w->t, w->client->key, w->client->name);
                },
                &u);
        }
    }
    for (auto& c : clients)
        if (c.fd >= 0) ::close(c.fd);
}

} // namespace armadillo::osc
