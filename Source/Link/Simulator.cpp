#include "Link/Simulator.h"
#include "Core/ThreadPriority.h"
#include "Core/Errors.h"
#include "Link/DeviceLink.h"
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

namespace armadillo::link {

// --- SensorModel -------------------------------------------------------------------------------

SensorModel::SensorModel(const SensorModelParams& params) : params_(params), rng_(params.seed) {}

Eigen::Vector3d SensorModel::gyroBias(double t) const
{
    const double decay = params_.gyroWarmup > 0.0 ? std::exp(-std::max(t, 0.0) / params_.gyroWarmup) : 0.0;
    return params_.gyroBiasSettled + (params_.gyroBiasStart - params_.gyroBiasSettled) * decay + walk_;
}

SensorCounts SensorModel::sample(const MotionState& motion, double t, const ProtocolLevels& motors)
{
    const double dt = std::clamp(t - lastT_, 0.0, 1.0);
    lastT_ = t;
    auto noise = [&](double rms) -> Eigen::Vector3d {
        const double x = normal_(rng_), y = normal_(rng_), z = normal_(rng_);
        return Eigen::Vector3d(x, y, z) * rms;
    };
    walk_ += noise(params_.gyroBiasWalk * std::sqrt(dt));

    const Eigen::Quaterniond toDevice = motion.q.conjugate();
    // Specific force: at rest the accelerometer reads +g along earth up (Y).
    const Eigen::Vector3d gravityUp(0.0, core::kStandardGravity, 0.0);
    double motorSum = 0.0;
    for (const auto m : motors) motorSum += m;
    const double accelRms = std::hypot(params_.accelNoise, params_.motorVibration * motorSum);
    truth_.t = t;
    truth_.accel = toDevice * gravityUp + motion.linearAccel;
    // Earth field: toward magnetic north (−Z) and dipping down (−Y).
    const double dip = core::degToRad(params_.dipDeg);
    const Eigen::Vector3d field(0.0, -std::sin(dip) * params_.fieldStrength, -std::cos(dip) * params_.fieldStrength);
    truth_.mag = toDevice * field;
    truth_.gyro = motion.omega;

    const Eigen::Vector3d a = truth_.accel + noise(accelRms);
    const Eigen::Vector3d g = truth_.gyro + gyroBias(t) + noise(params_.gyroNoise);
    const Eigen::Vector3d m = truth_.mag + noise(params_.magNoise);
    const Eigen::Vector3d ca = params_.adc.accel.toCounts(a), cg = params_.adc.gyro.toCounts(g), cm = params_.adc.mag.toCounts(m);
    auto adc = [](double c) { return static_cast<std::uint16_t>(std::clamp(std::lround(c), 0L, static_cast<long>(kMaxCount))); };
    return SensorCounts {adc(ca.x()), adc(ca.y()), adc(ca.z()), adc(cg.x()), adc(cg.y()), adc(cg.z()), adc(cm.x()), adc(cm.y()), adc(cm.z())};
}

// --- ForearmDevice -----------------------------------------------------------------------------

ForearmDevice::ForearmDevice(std::shared_ptr<const MotionSource> motion, const SensorModelParams& params)
    : motion_(std::move(motion)), sensors_(params)
{
    if (!motion_) motion_ = std::make_shared<WanderingMotion>();
}

bool ForearmDevice::onByte(std::uint8_t byte) noexcept
{
    const auto e = protocol_.onByte(byte);
    return e == DeviceProtocol::Event::MotorPacket || e == DeviceProtocol::Event::Resynced;
}

SensorPacketBytes ForearmDevice::answer(double t)
{
    lastCounts_ = sensors_.sample(motion_->at(t), t, protocol_.levels());
    return encodeSensorPacket(lastCounts_);
}

// --- SimulatedForearm --------------------------------------------------------------------------

class SimulatedForearm::InProcessPort final : public FdPort {
public:
    explicit InProcessPort(SimulatedForearm* sim) : sim_(sim) {}
    ~InProcessPort() override { FdPort::close(); }
    std::string name() const override { return "simulator"; }
    std::string backend() const override { return isOpen() ? "simulator" : ""; }
    void open() override
    {
        if (isOpen()) return;
        const int fd = sim_->takeHostFd();
        if (fd < 0) throw core::IoError("the simulated forearm is unplugged");
        adopt(fd, true);
    }

private:
    SimulatedForearm* sim_;
};

SimulatedForearm::SimulatedForearm(std::shared_ptr<const MotionSource> motion, const SimulatorOptions& options)
    : options_(options), device_(std::move(motion), options.sensors), rng_(options.seed)
{
    start_ = std::chrono::steady_clock::now();
}

SimulatedForearm::~SimulatedForearm() { stop(); }

double SimulatedForearm::now() const noexcept
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void SimulatedForearm::startPty(const std::string& linkPath)
{
    if (thread_.joinable()) throw std::logic_error("simulator already started");
    pty_ = true;
    linkPath_ = linkPath;
    if (!plug()) throw core::IoError("cannot create a pseudo-terminal for the simulator at " + linkPath + ": " + std::strerror(errno));
    stop_.store(false);
    thread_ = std::thread([this] { run(); });
}

std::unique_ptr<LinkPort> SimulatedForearm::startInProcess()
{
    if (thread_.joinable()) throw std::logic_error("simulator already started");
    pty_ = false;
    if (!plug()) throw core::IoError(std::string("cannot create the simulator's socket pair: ") + std::strerror(errno));
    stop_.store(false);
    thread_ = std::thread([this] { run(); });
    return std::make_unique<InProcessPort>(this);
}

void SimulatedForearm::stop()
{
    if (thread_.joinable()) {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stop_.store(true);
        }
        cv_.notify_all();
        thread_.join();
    }
    unplug();
}

int SimulatedForearm::takeHostFd()
{
    std::lock_guard<std::mutex> lock(mutex_);
    const int fd = hostFd_;
    hostFd_ = -1;
    return fd;
}

bool SimulatedForearm::plug()
{
    if (pty_) {
        termios raw {};
        ::cfmakeraw(&raw);
        raw.c_cflag |= CLOCAL | CREAD;
        int master = -1, slave = -1;
        if (::openpty(&master, &slave, nullptr, &raw, nullptr) != 0) return false;
        const char* name = ::ttyname(slave);
        if (!name) {
            ::close(master);
            ::close(slave);
            return false;
        }
        const std::string tmp = linkPath_ + ".new";
        ::unlink(tmp.c_str());
        if (::symlink(name, tmp.c_str()) != 0 || ::rename(tmp.c_str(), linkPath_.c_str()) != 0) {
            const int e = errno;
            ::close(master);
            ::close(slave);
            errno = e;
            return false;
        }
        ::fcntl(master, F_SETFL, ::fcntl(master, F_GETFL) | O_NONBLOCK);
        ::fcntl(master, F_SETFD, FD_CLOEXEC);
        ::fcntl(slave, F_SETFD, FD_CLOEXEC);
        fd_ = master;
        slaveKeep_ = slave;
        std::lock_guard<std::mutex> lock(mutex_);
        ptyName_ = name;
        ++stats_.connections;
        stats_.lastPlug = std::chrono::steady_clock::now();
    } else {
        int sv[2];
        if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) != 0) return false;
        ::fcntl(sv[0], F_SETFL, ::fcntl(sv[0], F_GETFL) | O_NONBLOCK);
        fd_ = sv[0];
        std::lock_guard<std::mutex> lock(mutex_);
        if (hostFd_ >= 0) ::close(hostFd_);
        hostFd_ = sv[1];
        ++stats_.connections;
        stats_.lastPlug = std::chrono::steady_clock::now();
    }
    device_.protocol().reset();   // power-up: wait for the host
    cv_.notify_all();
    return true;
}

void SimulatedForearm::unplug()
{
    if (fd_ >= 0) ::close(fd_);
    if (slaveKeep_ >= 0) ::close(slaveKeep_);
    fd_ = slaveKeep_ = -1;
    if (pty_ && !linkPath_.empty()) ::unlink(linkPath_.c_str());
    std::lock_guard<std::mutex> lock(mutex_);
    ptyName_.clear();
    if (hostFd_ >= 0) ::close(hostFd_);
    hostFd_ = -1;
}

bool SimulatedForearm::sleepUnlessStopped(double seconds)
{
    std::unique_lock<std::mutex> lock(mutex_);
    return !cv_.wait_for(lock, std::chrono::duration<double>(std::max(seconds, 0.0)), [&] { return stop_.load(); });
}

void SimulatedForearm::waitUntil(double t)
{
    // Absolute sleep to ~200 µs before, then yield: the wake-up latency of a busy machine is
    // absorbed and paced mode keeps the wire timing within a few µs.
    const double ahead = t - now();
    if (ahead <= 0.0) return;
    if (ahead > 250e-6) {
        const auto target = start_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(t - 200e-6));
        const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(target.time_since_epoch()).count();
        timespec ts {static_cast<time_t>(ns / 1000000000), static_cast<long>(ns % 1000000000)};
        while (::clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {}
    }
    while (now() < t) std::this_thread::yield();
}

void SimulatedForearm::respond(double rxTime)
{
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const FaultConfig& f = options_.faults;
    // Stalls and unplugs first: the device stops answering.
    double stall = stallSeconds_.exchange(0.0);
    if (stall <= 0.0 && f.stall > 0.0 && u(rng_) < f.stall) stall = f.stallSeconds;
    if (stall > 0.0) {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            ++stats_.faults;
        }
        if (!sleepUnlessStopped(stall)) return;
    }
    double unplugFor = disconnectSeconds_.exchange(0.0);
    if (unplugFor <= 0.0 && f.disconnect > 0.0 && u(rng_) < f.disconnect) unplugFor = f.disconnectSeconds;
    if (unplugFor > 0.0) {
        unplug();
        unpluggedUntil_ = now() + unplugFor;
        std::lock_guard<std::mutex> lock(mutex_);
        ++stats_.faults;
        cv_.notify_all();
        return;
    }

    if (options_.baud > 0.0) {
        // 8N1 wire: the host's packet occupied the wire until rxTime + 5 byte times (it was written
        // at once); the 14 answer bytes take 14 more. Bytes reach the host when the last one is done.
        const double byteTime = 10.0 / options_.baud;
        const double startSend = std::max(rxTime + static_cast<double>(kMotorPacketSize) * byteTime, wireFree_);
        wireFree_ = startSend + static_cast<double>(kSensorPacketSize) * byteTime;
        waitUntil(wireFree_);
    }

    SensorPacketBytes packet = device_.answer(now());
    if (options_.stampSequence) {
        SensorCounts c = device_.lastCounts();
        std::lock_guard<std::mutex> lock(mutex_);
        c[kAx] = static_cast<std::uint16_t>(stats_.packetsSent & 0x0FFF);
        packet = encodeSensorPacket(c);
    }
    std::uint8_t out[kSensorPacketSize + 1];
    std::size_t n = kSensorPacketSize;
    std::copy(packet.begin(), packet.end(), out);
    int faults = 0;
    std::uniform_int_distribution<int> anyByte(0, static_cast<int>(kSensorPacketSize) - 1);
    std::uniform_int_distribution<int> anyBits(1, 255);
    if (corruptEnd_.exchange(0) > 0) {
        out[kSensorPacketSize - 1] = static_cast<std::uint8_t>((out[kSensorPacketSize - 1] & 0xF0) | 0x05);
        ++faults;
    }
    if (f.corruptPacket > 0.0 && u(rng_) < f.corruptPacket) {
        out[anyByte(rng_)] ^= static_cast<std::uint8_t>(anyBits(rng_));
        ++faults;
    }
    const bool drop = dropByte_.exchange(0) > 0 || (f.dropByte > 0.0 && u(rng_) < f.dropByte);
    if (drop) {
        const int i = anyByte(rng_);
        std::copy(out + i + 1, out + n, out + i);
        --n;
        ++faults;
    }
    const bool scriptedInsert = insertByte_.exchange(0) > 0;
    if (scriptedInsert || (f.insertByte > 0.0 && u(rng_) < f.insertByte)) {
        const std::uint8_t value = scriptedInsert ? static_cast<std::uint8_t>(insertValue_.load()) : static_cast<std::uint8_t>(anyBits(rng_));
        const int i = scriptedInsert ? 0 : anyByte(rng_);
        std::copy_backward(out + i, out + n, out + n + 1);
        out[i] = value;
        ++n;
        ++faults;
    }

    std::size_t done = 0;
    for (int tries = 0; done < n && tries < 50; ++tries) {
        const ssize_t w = pty_ ? ::write(fd_, out + done, n - done) : ::send(fd_, out + done, n - done, MSG_NOSIGNAL | MSG_DONTWAIT);
        if (w > 0) {
            done += static_cast<std::size_t>(w);
            continue;
        }
        if (w < 0 && errno != EAGAIN && errno != EINTR) break;
        pollfd p {fd_, POLLOUT, 0};
        ::poll(&p, 1, 2);
    }
    std::lock_guard<std::mutex> lock(mutex_);
    ++stats_.packetsSent;
    stats_.faults += static_cast<std::uint64_t>(faults);
    stats_.levels = device_.protocol().levels();
    cv_.notify_all();
}

void SimulatedForearm::run()
{
    ::prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);   // precise paced sleeps
    core::requestRealtimePriority(options_.realtimePriority);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::uint8_t buffer[256];
    while (!stop_.load(std::memory_order_relaxed)) {
        if (fd_ < 0) {
            const double wait = unpluggedUntil_ - now();
            if (wait > 0.0) {
                sleepUnlessStopped(wait);
                continue;
            }
            if (!plug()) {
                sleepUnlessStopped(0.05);
                continue;
            }
        }
        if (const double s = disconnectSeconds_.load(); s > 0.0) {
            // A scripted unplug also happens while the host is silent.
            disconnectSeconds_.store(0.0);
            unplug();
            unpluggedUntil_ = now() + s;
            std::lock_guard<std::mutex> lock(mutex_);
            ++stats_.faults;
            cv_.notify_all();
            continue;
        }
        pollfd p {fd_, POLLIN, 0};
        const int r = ::poll(&p, 1, 10);
        if (r <= 0) continue;
        if (!(p.revents & POLLIN)) {
            if (p.revents & (POLLHUP | POLLERR | POLLNVAL)) {
                unplug();   // the host end went away (in-process): plug in again at once
                unpluggedUntil_ = now();
            }
            continue;
        }
        const ssize_t n = ::read(fd_, buffer, sizeof buffer);
        if (n == 0 || (n < 0 && errno != EAGAIN && errno != EINTR && errno != EIO)) {
            unplug();
            unpluggedUntil_ = now();
            continue;
        }
        if (n < 0) continue;
        const double rxTime = now();
        for (ssize_t i = 0; i < n && fd_ >= 0 && !stop_.load(std::memory_order_relaxed); ++i) {
            std::uint8_t b = buffer[i];
            if (options_.faults.corruptHostByte > 0.0 && u(rng_) < options_.faults.corruptHostByte) {
                b ^= static_cast<std::uint8_t>(1u << (rng_() % 8));
                std::lock_guard<std::mutex> lock(mutex_);
                ++stats_.faults;
            }
            const auto e = device_.protocol().onByte(b);
            if (e == DeviceProtocol::Event::None) continue;
            {
                std::lock_guard<std::mutex> lock(mutex_);
                if (e == DeviceProtocol::Event::MotorPacket) {
                    ++stats_.motorPackets;
                    for (std::uint8_t level : device_.protocol().levels())
                        stats_.maxLevelApplied = std::max<int>(stats_.maxLevelApplied, level);
                }
                if (e == DeviceProtocol::Event::BadPacket) ++stats_.badMotorPackets;
                if (e == DeviceProtocol::Event::Resynced) ++stats_.resyncAnswers;
            }
            if (e == DeviceProtocol::Event::MotorPacket || e == DeviceProtocol::Event::Resynced) respond(rxTime);
        }
    }
}

void SimulatedForearm::corruptNextEndNibble() { corruptEnd_.store(1); }
void SimulatedForearm::dropNextByte() { dropByte_.store(1); }
void SimulatedForearm::insertNextByte(std::uint8_t value)
{
    insertValue_.store(value);
    insertByte_.store(1);
}
void SimulatedForearm::stallFor(double seconds) { stallSeconds_.store(seconds); }
void SimulatedForearm::disconnectFor(double seconds)
{
    disconnectSeconds_.store(seconds);
}

SimulatorStats SimulatedForearm::stats() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return stats_;
}

std::string SimulatedForearm::ptyPath() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return ptyName_;
}

bool SimulatedForearm::waitFor(const std::function<bool(const SimulatorStats&)>& pred, double timeoutSeconds) const
{
    std::unique_lock<std::mutex> lock(mutex_);
    return cv_.wait_for(lock, std::chrono::duration<double>(timeoutSeconds), [&] { return pred(stats_); });
}

} // namespace armadillo::link
