#include "Live/Sources/DeviceConnection.h"
#include "Link/DeviceLink.h"
#include "Live/Sources/SourceRegistry.h"
#include "Core/Clock.h"
#include <csignal>
#include <cstdio>
#include <pthread.h>
#include <exception>

namespace armadillo::live {

DeviceConnection::DeviceConnection(LiveInput& input, link::LevelSchedule& motors, ArmSourceSlot& slot)
    : input_(input), motors_(motors), calibration_(link::defaultCalibration()), source_(slot)
{
}

DeviceConnection::~DeviceConnection()
{
    disconnect();
}

bool DeviceConnection::connect(const std::string& port, int baud, const std::string& calibrationFile, std::string& message)
{
    disconnect();
    message.clear();
    if (port.empty()) {
        message = "Choose a serial port first.";
        return false;
    }
    calibration_ = link::defaultCalibration();
    calibrationNote_ = "default calibration";
    if (! calibrationFile.empty()) {
        try {
            calibration_ = link::loadCalibration(calibrationFile);
            calibrationNote_ = "calibration " + calibrationFile;
        } catch (const std::exception& e) {
            message = std::string("Calibration not loaded (") + e.what() + "); using the default calibration. ";
        }
    }

    // The link and simulator threads inherit this thread's signal mask: with SIGPIPE blocked a
    // write to a vanished peer returns EPIPE instead of killing the host (a DAW) with SIGPIPE.
    sigset_t pipe, previous;
    sigemptyset(&pipe);
    sigaddset(&pipe, SIGPIPE);
    pthread_sigmask(SIG_BLOCK, &pipe, &previous);
    struct RestoreMask {
        sigset_t mask;
        ~RestoreMask() { pthread_sigmask(SIG_SETMASK, &mask, nullptr); }
    } restore {previous};

    ArmSourceDescription description;
    description.kind = ArmSourceDescription::Kind::Forearm;
    ForearmPortRequest& request = description.forearm;
    request.simulate = port == kSimulatedPort;
    request.port = port;
    request.baud = baud;
    request.openNow = false;   // a missing port: the link waits for it, the status says so
    request.simulatorBaud = 57600.0;   // paced like the thesis's Bluetooth serial link
    request.simulatorPriority = kLinkPriority - 1;   // the board's side of the wire keeps time too
    // The link is the last stage before the motors: a packet it writes late holds the previous
    // levels longer than the safety stage planned (its horizon is 25 ms). It asks for
    // SCHED_FIFO, as `armadillo play` does (falls back silently where that is not allowed).
    description.link.realtimePriority = kLinkPriority;
    try {
        if (request.simulate) {
            calibration_ = link::defaultCalibration();   // the simulator's ADC is the default one
            calibrationNote_ = "simulator's calibration";
        } else {
            std::string why;
            claim_ = PortRegistry::claim(port, why);
            if (claim_ == nullptr) {
                message += why + ". Choose another port, or follow that instance over OSC.";
                return false;
            }
        }
        publishCalibration();
        packetSafety_.prepare(tactile::kDefaultSafetyParams, core::kMaxMotors); // allocates: here, before the link thread starts
        lastPacketAt_ = -1.0;
        linkSeen_ = 0;
        linkGeneration_.store(0, std::memory_order_release);
        ArmSourceHandlers handlers;
        handlers.onPacket = [this](const link::SensorCounts& counts, double t) {
            // A calibration published by the message thread (connect, guided calibration) is
            // taken up here, between packets: a seqlock read, no lock, no allocation.
            const std::uint64_t generation = pendingGeneration_.load(std::memory_order_acquire);
            if (generation != linkSeen_) {
                fromNumbers(pendingCalibration_.load(), linkCalibration_);
                linkSeen_ = generation;
                linkGeneration_.store(generation, std::memory_order_release);
            }
            calibrationSession_.offer(t, counts);   // raw counts, only while a guided calibration runs
            input_.pushImu(linkCalibration_.apply(t, counts));   // full queue: the control loop is behind; drop, never block
            // The levels whose time has come on the control steps' clock (not the link's t, which
            // follows the board's clock in v2): all-off when they went stale.
            const double now = core::monotonicSeconds();
            const core::MotorLevels due = motors_.due(now);
            // The control steps' safety stage planned each level for ≥ 25 ms on the motor; the
            // packet timeline's own stage holds the bounds when packets come further apart.
            const double held = lastPacketAt_ < 0.0 ? 0.0 : now - lastPacketAt_;
            lastPacketAt_ = now;
            return packetSafety_.process(due, held);
        };
        link_ = source_.open(description, std::move(handlers)).link();   // the simulated forearm starts here
        if (sentLog_) link_->enableSentLog();
        linkEpoch_ = core::monotonicSeconds();
        source_->start();
    } catch (const std::exception& e) {
        link_ = nullptr;
        source_.close();   // stops the simulated forearm
        claim_.reset();
        message += std::string("Cannot open ") + port + ": " + e.what();
        return false;
    }
    message += "Connected to " + port + " (" + calibrationNote_ + ").";
    return true;
}

void DeviceConnection::disconnect()
{
    if (calibrationSession_.running()) calibrationSession_.cancel("the device was disconnected");
    if (ArmSource* source = source_.get()) source->stop();   // no motor packet leaves after this; then the simulated forearm stops
    link_ = nullptr;
    source_.close();
    claim_.reset();
}

DeviceConnection::CalibrationNumbers DeviceConnection::toNumbers(const link::Calibration& c) noexcept
{
    CalibrationNumbers n;
    const link::SensorCalibration* parts[3] {&c.accel, &c.gyro, &c.mag};
    for (int k = 0; k < 3; ++k) {
        for (int i = 0; i < 3; ++i) {
            n.sensor[k][i] = parts[k]->bias[i];
            n.sensor[k][3 + i] = parts[k]->scale[i];
            for (int j = 0; j < 3; ++j) n.sensor[k][6 + 3 * i + j] = parts[k]->cross(i, j);
        }
    }
    return n;
}

void DeviceConnection::fromNumbers(const CalibrationNumbers& n, link::Calibration& c) noexcept
{
    link::SensorCalibration* parts[3] {&c.accel, &c.gyro, &c.mag};
    for (int k = 0; k < 3; ++k) {
        for (int i = 0; i < 3; ++i) {
            parts[k]->bias[i] = n.sensor[k][i];
            parts[k]->scale[i] = n.sensor[k][3 + i];
            for (int j = 0; j < 3; ++j) parts[k]->cross(i, j) = n.sensor[k][6 + 3 * i + j];
        }
    }
}

void DeviceConnection::publishCalibration() noexcept
{
    pendingCalibration_.store(toNumbers(calibration_));
    pendingGeneration_.store(++requestedGeneration_, std::memory_order_release);
}

void DeviceConnection::applyCalibration(const link::Calibration& calibration, const std::string& note)
{
    calibration_ = calibration;
    calibrationNote_ = note;
    publishCalibration();
}

bool DeviceConnection::popSent(double& t, core::MotorLevels& levels) noexcept
{
    if (link_ == nullptr) return false;
    link::SentMotorPacket p;
    if (! link_->sentLog().pop(p)) return false;
    t = linkEpoch_ + p.t;
    levels = {};
    for (std::size_t m = 0; m < p.levels.size() && m < levels.size(); ++m) levels[m] = p.levels[m];
    return true;
}

std::uint64_t DeviceConnection::sentDropped() const noexcept
{
    return link_ == nullptr ? 0 : link_->sentLogDropped();
}

std::uint64_t DeviceConnection::packetsReceived() const noexcept
{
    return link_ == nullptr ? 0 : link_->stats().packets;
}

std::string DeviceConnection::status() const
{
    if (link_ == nullptr) return "Not connected.";
    const auto s = link_->stats();
    char buffer[256];
    std::snprintf(buffer, sizeof(buffer),
                  "%s %s (%s): %llu packets, %llu bad, %llu resyncs, %llu reconnects, %llu gaps (longest %.2f s), %.0f/s",
                  link_->connected() ? "Linked to" : "Waiting for", link_->portName().c_str(), link_->backend().c_str(),
                  static_cast<unsigned long long>(s.packets), static_cast<unsigned long long>(s.badPackets),
                  static_cast<unsigned long long>(s.resyncs), static_cast<unsigned long long>(s.reconnects),
                  static_cast<unsigned long long>(s.gaps), s.longestGap, s.rateHz);
    std::string out = buffer;
    const auto error = link_->lastError();
    if (! error.empty()) out += "\nLast error: " + error;
    return out;
}

} // namespace armadillo::live
