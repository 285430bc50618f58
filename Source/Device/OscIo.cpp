#include "Device/OscIo.h"
#include "Core/Errors.h"
#include "Core/Pose.h"
#include <arpa/inet.h>
#include <cerrno>
#include <charconv>
#include <cmath>
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

OscReceiver::OscReceiver(int port, ImuHandler onImu, OrientationHandler onOrientation)
    : onImu_(std::move(onImu)), onOrientation_(std::move(onOrientation))
{
    if (port < 0 || port > 65535) throw IoError("OSC in: port " + std::to_string(port) + " is outside 0..65535");
    fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (fd_ < 0) throw IoError(std::string("OSC in: cannot create a UDP socket: ") + std::strerror(errno));
    sockaddr_in a {};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_ANY);
    a.sin_port = htons(static_cast<std::uint16_t>(port));
    if (::bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
        const int e = errno;
        ::close(fd_);
        fd_ = -1;
        throw IoError("OSC in: cannot listen on UDP port " + std::to_string(port) + ": " + std::strerror(e));
    }
    socklen_t len = sizeof a;
    ::getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &len);
    port_ = ntohs(a.sin_port);
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

OscInputStats OscReceiver::stats() const noexcept
{
    return OscInputStats {datagrams_.load(), imu_.load(), orientation_.load(), bad_.load(), ignored_.load()};
}

std::string OscReceiver::lastError() const
{
    while (errorLock_.exchange(true, std::memory_order_acquire)) {}
    std::string e = lastError_;
    errorLock_.store(false, std::memory_order_release);
    return e;
}

void OscReceiver::handleDatagram(const std::uint8_t* data, std::size_t size, double t)
{
    datagrams_.fetch_add(1, std::memory_order_relaxed);
    std::string error;
    bool badArgs = false;
    const bool ok = decodeOscPacket(data, size, [&](const OscMessage& m) {
        double v[9];
        auto numbers = [&](int n) {
            if (m.count != n) return false;
            for (int i = 0; i < n; ++i)
                if (!m.args[i].asNumber(v[i]) || !std::isfinite(v[i])) return false;
            return true;
        };
        if (m.address == "/armadillo/imu") {
            // gx gy gz ax ay az mx my mz (SI); the magnetometer may be absent (6 numbers).
            const bool nine = numbers(9);
            if (!nine && !numbers(6)) {
                badArgs = true;
                error = "/armadillo/imu needs 9 numbers (gx gy gz ax ay az mx my mz) or 6 without the magnetometer";
                return;
            }
            ImuSample s;
            s.t = t;
            s.gyro = Eigen::Vector3d(v[0], v[1], v[2]);
            s.accel = Eigen::Vector3d(v[3], v[4], v[5]);
            if (nine) s.mag = Eigen::Vector3d(v[6], v[7], v[8]);
            imu_.fetch_add(1, std::memory_order_relaxed);
            if (onImu_) onImu_(s);
        } else if (m.address == "/armadillo/orientation") {
            if (!numbers(4) || std::hypot(v[0], v[1], v[2]) + std::abs(v[3]) < 1e-9) {
                badArgs = true;
                error = "/armadillo/orientation needs 4 finite numbers w x y z, not all zero";
                return;
            }
            const Eigen::Quaterniond q = Eigen::Quaterniond(v[0], v[1], v[2], v[3]).normalized();
            orientation_.fetch_add(1, std::memory_order_relaxed);
            if (onOrientation_) onOrientation_(t, q);
        } else {
            ignored_.fetch_add(1, std::memory_order_relaxed);
        }
    }, &error);
    if (!ok || badArgs) {
        bad_.fetch_add(1, std::memory_order_relaxed);
        while (errorLock_.exchange(true, std::memory_order_acquire)) {}
        lastError_ = error;
        errorLock_.store(false, std::memory_order_release);
    }
}

void OscReceiver::run()
{
    std::vector<std::uint8_t> buffer(65536);
    while (!stop_.load(std::memory_order_relaxed)) {
        pollfd p {fd_, POLLIN, 0};
        if (::poll(&p, 1, 20) <= 0) continue;
        const ssize_t n = ::recv(fd_, buffer.data(), buffer.size(), MSG_DONTWAIT);
        if (n <= 0) continue;
        const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
        handleDatagram(buffer.data(), static_cast<std::size_t>(n), t);
    }
}

} // namespace armadillo::device
