#pragma once
// OSC over UDP: the sender for the INTERFACES.md address space (`--osc-out HOST:PORT`, the
// plugin's OSC setting) and the sensor input (`--osc-in PORT`): ARMadillo's own /armadillo/imu
// and /armadillo/orientation, and the dialects of phone apps and the NGIMU (OscDialects.h),
// merged into IMU samples by OscSampleMerger (OscInput.h), so what people own drives everything.
#include "Core/Types.h"
#include "Osc/HostPort.h"
#include "Osc/Osc.h"
#include "Osc/OscInput.h"
#include <Eigen/Geometry>
#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <thread>

namespace armadillo::core {
struct Pose;
}
namespace armadillo::link {
class LinkPort;
}

namespace armadillo::osc {


/// Sends datagrams without blocking (a full socket buffer drops the message). Messages are
/// encoded on the stack: safe to call from the control thread.
class OscSender {
public:
    /// Resolves the destination; throws IoError when it cannot (unknown host, no socket).
    explicit OscSender(const HostPort& destination);
    ~OscSender();
    OscSender(const OscSender&) = delete;
    OscSender& operator=(const OscSender&) = delete;

    bool send(std::string_view address, const OscArg* args, std::size_t count) noexcept;
    /// An already-encoded packet (a mapping's OSC message, Mapping/Mapper.h). Real-time like send().
    bool sendPacket(const std::uint8_t* data, std::size_t size) noexcept;
    bool sendOrientation(const Eigen::Quaterniond& q) noexcept;   ///< /armadillo/orientation ffff (w x y z)
    bool sendPose(const core::Pose& pose) noexcept;               ///< /armadillo/pose fff (elevation azimuth roll, deg)
    bool sendGyro(const Eigen::Vector3d& gyro) noexcept;          ///< /armadillo/gyro fff (rad/s, device frame)
    bool sendMotors(const core::MotorLevels& levels, int motorCount = core::kGridMotors) noexcept; ///< /armadillo/motors i…
    bool sendGesture(const char* name) noexcept;                  ///< /armadillo/gesture s

    std::uint64_t sent() const noexcept { return sent_.load(); }
    std::uint64_t dropped() const noexcept { return dropped_.load(); }

private:
    int fd_ = -1;
    alignas(8) unsigned char addr_[128] {};
    unsigned addrLen_ = 0;
    std::atomic<std::uint64_t> sent_ {0}, dropped_ {0};
};

/// A serial port that carries SLIP-framed OSC (the NGIMU over USB): `play --port NAME --format ngimu-slip`.
struct OscSerialSource {
    std::string path;
    int baud = 115200;   ///< a USB CDC port ignores it; the NGIMU's auxiliary serial default
};

/// A UDP socket bound to `port` on every interface: one IPv6 socket that also takes IPv4 (as
/// v4-mapped addresses), or plain IPv4 when the machine has no IPv6. Returns the descriptor and
/// the port actually bound (`port` 0 picks a free one). Throws IoError starting with `who`.
int bindUdpAnyInterface(int port, const std::string& who, int& boundPort);
/// A UDP socket bound to `port` on one address (Osc/AllowList.h): a numeric IPv4 or IPv6
/// address ("127.0.0.1", "192.168.1.20", "0.0.0.0" = every IPv4 interface, "::" = every
/// interface, IPv6 and IPv4); "" is bindUdpAnyInterface. Throws IoError starting with `who`.
int bindUdp(const std::string& address, int port, const std::string& who, int& boundPort);

/// Listens on a UDP port and the same TCP port (all interfaces) on its own thread, or reads
/// SLIP-framed OSC from a serial port; handlers run on that thread. UDP datagrams are OSC or ZIG
/// SIM JSON (first byte); TCP connections carry ZIG SIM's unframed stream (OscStream.h).
class OscReceiver {
public:
    using ImuHandler = std::function<void(const core::ImuSample&)>;
    using OrientationHandler = std::function<void(double t, const Eigen::Quaterniond& q)>;

    /// Binds now (port 0 = any free port); throws IoError when the UDP port is taken. A TCP port
    /// that is taken only loses the TCP input (tcpError() says why).
    OscReceiver(int port, ImuHandler onImu, OrientationHandler onOrientation, const OscInputOptions& options = {});
    /// Reads the serial port (opened now: IoError when it is not there; reopened when it goes away).
    OscReceiver(const OscSerialSource& serial, ImuHandler onImu, OrientationHandler onOrientation, const OscInputOptions& options = {});
    ~OscReceiver();
    OscReceiver(const OscReceiver&) = delete;
    OscReceiver& operator=(const OscReceiver&) = delete;

    void start();
    void stop();
    int port() const noexcept { return port_; }
    /// "" when TCP listens on port() too; else why not.
    const std::string& tcpError() const noexcept { return tcpError_; }
    /// The serial port read (empty for UDP/TCP) and its latest I/O error ("" when none).
    const std::string& serialPath() const noexcept { return serial_.path; }
    std::string serialError() const;
    /// TCP connections accepted so far.
    std::uint64_t tcpConnections() const noexcept { return tcpAccepted_.load(); }
    OscInputStats stats() const noexcept { return merger_.stats(); }
    /// The latest reason a message was refused ("" when none). Not for the control path.
    std::string lastError() const { return merger_.lastError(); }
    /// The dialect in use (Auto until the first recognised message) and the chosen device.
    OscFormat format() const noexcept { return merger_.format(); }
    std::string deviceName() const { return merger_.deviceName(); }
    /// The counters as JSON members (for the session summary).
    std::string statsJson() const { return oscStatsJson(stats(), oscFormatName(format()), deviceName()); }
    OscSampleMerger& merger() noexcept { return merger_; }
    const OscSampleMerger& merger() const noexcept { return merger_; }
    /// Decodes and dispatches one datagram at time t (what the thread does; public for tests/fuzz).
    void handleDatagram(const std::uint8_t* data, std::size_t size, double t, std::uint64_t senderKey = 0, const char* senderName = "");
    /// Another reader of every UDP/TCP datagram (an OSC packet or ZIG SIM JSON), called on the
    /// receiver's thread before the sensor dialects see it: `navigate` takes positions from the
    /// same port as the arm's motion (ZIG SIM's gps). Set before start(); must not block.
    using DatagramTap = std::function<void(const std::uint8_t* data, std::size_t size)>;
    void setDatagramTap(DatagramTap tap) { tap_ = std::move(tap); }

private:
    struct TcpClient;
    void run();
    void runSerial();
    void acceptTcp(double now);
    double now() const noexcept;
    int fd_ = -1;
    int tcpFd_ = -1;
    int port_ = 0;
    std::string tcpError_;
    std::atomic<std::uint64_t> tcpAccepted_ {0};
    OscSerialSource serial_;
    std::unique_ptr<link::LinkPort> serialPort_;
    mutable std::atomic<bool> serialErrorLock_ {false};
    std::string serialError_;
    ImuHandler onImu_;
    OrientationHandler onOrientation_;
    DatagramTap tap_;
    OscSampleMerger merger_;
    int realtimePriority_ = 0;   ///< OscInputOptions::realtimePriority, for the receiving thread
    std::thread thread_;
    std::atomic<bool> stop_ {false};
    std::chrono::steady_clock::time_point start_ {};
};

} // namespace armadillo::osc
