#pragma once
// The instrument's source registry: every source the live instrument reads is constructed here
// and nowhere else, from a description (scripts/check-structure.py holds it so):
//   - a forearm: a serial port (the real device, a Bluetooth serial link) or the device module's
//     simulated forearm, in-process, read by a DeviceLink on its own thread;
//   - an OSC sender: a UDP (and TCP) port or a SLIP serial port, read by an OscReceiver (the
//     thesis's own OSC, the phone apps, NGIMU; docs/SENSORS.md);
//   - the messages read on the arm: an MQTT client and its inbox (MessageService).
// Positions for a walk (gpsd, OSC positions, the simulated walker) are built by
// navigation::NavigationRig::open, the one place that knows a route. Host automation and Pd's
// inlets are not sources of their own: they write the same mailbox (LiveInput) as these do.
//
// Who asks: `armadillo play`/`read`/`navigate` and Pd's [armadillo] (LiveSession, both arms),
// the app's and plugin's device and OSC inputs (DeviceConnection, OscInput), the command line's
// guided procedures (GuidedDevice) and the block instrument's messages (MessagesRig). They differ
// only in what they describe: probe a port now or let the link wait for it, how a simulated arm
// moves and how fast its link is paced, which OSC port and dialect.
#include "Link/DeviceLink.h"
#include "Link/Motion.h"
#include "Mqtt/ArmMessages.h"
#include "Mqtt/MqttConfig.h"
#include "Osc/OscIo.h"
#include <cstdint>
#include <memory>
#include <string>

namespace armadillo::link {
class LinkPort;
class SimulatedForearm;
} // namespace armadillo::link

namespace armadillo::mqtt {
class MessageService;
}

namespace armadillo::live {

struct ForearmPortRequest {
    bool simulate = false;       ///< the simulated forearm instead of `port`
    std::string port;            ///< serial port path (not simulated)
    int baud = 57600;
    /// Not simulated: open the port now, so a missing or busy port is an IoError naming it
    /// (exit 4 on the command line). Off: the link opens it, and retries while it is missing
    /// (the app's device source, which reports "Waiting for" instead).
    bool openNow = true;
    /// Simulated: how the arm moves (null: the wandering arm with `seed`), the link's pace in
    /// baud (0: unpaced, as fast as the reader takes it) and the board thread's SCHED_FIFO
    /// priority (0: none).
    std::shared_ptr<const link::MotionSource> motion;
    std::uint64_t seed = 1;
    double simulatorBaud = 57600.0;
    int simulatorPriority = 0;
};

/// An opened forearm port. A simulated one owns its simulator: stop the link reading `port`
/// first, then the simulator (stop() or the destructor).
struct ForearmPort {
    std::unique_ptr<link::LinkPort> port;
    std::unique_ptr<link::SimulatedForearm> simulator;

    ForearmPort();
    ForearmPort(ForearmPort&&) noexcept;
    ForearmPort& operator=(ForearmPort&&) noexcept;
    ~ForearmPort();
};

/// Opens the port `request` names (a probe: Pd's [armadillo~] asks whether a port opens). Throws
/// IoError for a port that cannot be opened (openNow).
ForearmPort openForearmPort(const ForearmPortRequest& request);

/// One arm's source, as the instrument describes it.
struct ArmSourceDescription {
    enum class Kind {
        Forearm,     ///< `forearm` (a port or the simulated forearm), read by a device link with `link`
        OscUdp,      ///< an OSC sender on UDP (and TCP) port `oscPort` (0: any free port)
        OscSerial,   ///< an OSC sender on a SLIP serial port (`oscSerial`)
    };
    Kind kind = Kind::Forearm;
    ForearmPortRequest forearm;
    link::DeviceLinkOptions link;
    int oscPort = 0;
    osc::OscSerialSource oscSerial;
    osc::OscInputOptions osc;   ///< dialect, mount, the receiving thread's priority
};

/// Where an arm source's data goes. Each runs on the source's own thread (real-time: no
/// allocation, lock or I/O): a forearm's packets answered with the motor levels to write; an OSC
/// sender's samples or its own orientations.
struct ArmSourceHandlers {
    link::DeviceLink::Handler onPacket;               ///< Forearm
    osc::OscReceiver::ImuHandler onImu;               ///< OSC
    osc::OscReceiver::OrientationHandler onOrientation;   ///< OSC
};

/// An opened arm source: a device link (and the simulated forearm it may read) or an OSC
/// receiver. Opened, not started: start() starts its thread. Stopping stops the reader first (no
/// motor packet leaves after the link stops), then the simulated forearm.
class ArmSource {
public:
    ~ArmSource();
    ArmSource(const ArmSource&) = delete;
    ArmSource& operator=(const ArmSource&) = delete;

    void start();
    void stop();
    /// The forearm's link (null for an OSC sender) and the OSC receiver (null for a forearm):
    /// statistics, the sent log, the sender's dialect.
    link::DeviceLink* link() noexcept { return link_.get(); }
    const link::DeviceLink* link() const noexcept { return link_.get(); }
    osc::OscReceiver* osc() noexcept { return osc_.get(); }
    const osc::OscReceiver* osc() const noexcept { return osc_.get(); }

private:
    friend std::unique_ptr<ArmSource> openArmSource(const ArmSourceDescription&, ArmSourceHandlers);
    ArmSource();
    std::unique_ptr<link::SimulatedForearm> simulator_;   // destroyed after the link that reads it
    std::unique_ptr<link::DeviceLink> link_;
    std::unique_ptr<osc::OscReceiver> osc_;
};

/// Opens the source `description` names. Throws IoError naming the port when it cannot be opened
/// (a missing serial port with openNow, a UDP port taken), InputError for a bad description.
std::unique_ptr<ArmSource> openArmSource(const ArmSourceDescription& description, ArmSourceHandlers handlers);

/// Where the instrument keeps one arm source (Live/Session/Instrument.h holds them: the right
/// arm's forearm and OSC sender, the left arm's): whoever drives that source — LiveSession from
/// its description, the block clock's DeviceConnection and OscInput as the user chooses — opens
/// it here through the registry and closes it here; the instrument closes what is still open
/// before the mailboxes the sources write. One thread at a time (the one that opens it).
class ArmSourceSlot {
public:
    ArmSourceSlot() = default;
    ~ArmSourceSlot() { close(); }
    ArmSourceSlot(const ArmSourceSlot&) = delete;
    ArmSourceSlot& operator=(const ArmSourceSlot&) = delete;

    /// Opens the source `description` names (the one open before is closed first), not started:
    /// openArmSource's errors.
    ArmSource& open(const ArmSourceDescription& description, ArmSourceHandlers handlers);
    /// Stops the source (its reader first: no motor packet leaves after this) and deletes it.
    void close() noexcept;
    ArmSource* get() noexcept { return source_.get(); }
    const ArmSource* get() const noexcept { return source_.get(); }
    explicit operator bool() const noexcept { return source_ != nullptr; }
    ArmSource* operator->() noexcept { return source_.get(); }

private:
    std::unique_ptr<ArmSource> source_;
};

/// The messages read on the arm: the MQTT client, its inbox and presenter, not yet connected
/// (start() connects; a broker that is down is no error, it keeps trying). InputError for a bad
/// configuration.
std::unique_ptr<mqtt::MessageService> openMessageSource(mqtt::MqttConfig config, mqtt::PresenterOptions options);

} // namespace armadillo::live
