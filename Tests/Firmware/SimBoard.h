#pragma once
// The reference firmware's compiled .elf running in simavr (ATmega2560 @ 16 MHz, cycle-exact) as a
// test fixture: a register-level MPU-9250 + AK8963 on the simulated I2C bus fed from a known motion,
// UART0 bridged to an in-process byte queue (timestamps in simulated time), and the nine motor PWM
// pins watched edge by edge so their duty can be read. Simulated time only: nothing here sleeps or
// reads a wall clock, so every figure is deterministic.
#include "Link/Motion.h"
#include "Link/Simulator.h"
#include <array>
#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <vector>

struct avr_t;
struct avr_irq_t;

namespace armadillo::firmware_test {

/// The MPU-9250 (0x68) and the AK8963 magnetometer behind its I2C bypass (0x0C), register by register.
/// Physical values come from the project's SensorModel (gravity, field with dip, gyro bias drift,
/// noise) for the motion at the simulated time of each read, converted into each chip's own axes
/// and full-scale settings as the firmware configured them.
class Mpu9250Model {
public:
    Mpu9250Model(std::shared_ptr<const link::MotionSource> motion, const link::SensorModelParams& params);
    /// One I2C message from simavr's TWI master (avr_twi_msg_irq_t value); returns true and sets
    /// `reply` when the model answers (ACK or a data byte).
    void onTwi(std::uint32_t msg, double t, avr_t* avr, avr_irq_t* replyIrq);
    bool present = true;               ///< false: nobody answers on the bus (tests the firmware's error path)
    std::array<std::uint8_t, 3> asa {176, 171, 165};   ///< AK8963 factory sensitivity adjustment (typical values)
    double fieldMicroTesla = 50.0;     ///< µT per "field unit" of the sensor model
    std::uint64_t mpuReads = 0, magReads = 0;
    link::ProtocolLevels motors {};  ///< for the model's motor vibration noise

private:
    void sampleMpu(double t);
    void updateMag(double t);
    std::shared_ptr<const link::MotionSource> motion_;
    link::SensorModel model_;
    std::array<std::uint8_t, 128> mpu_ {};
    std::array<std::uint8_t, 0x13> ak_ {};
    int selected_ = 0;                 ///< 0 none, 1 MPU, 2 AK8963
    bool havePointer_ = false;
    std::uint8_t ptr_ = 0;
    double nextMag_ = -1.0;            ///< s: next AK8963 measurement in continuous mode
    double lastSample_ = -1.0;
    core::ImuSample truth_ {};
};

class SimBoard {
public:
    struct Options {
        std::string elf;
        std::shared_ptr<const link::MotionSource> motion = std::make_shared<link::WanderingMotion>();
        link::SensorModelParams sensors {};
        bool imuPresent = true;
        /// simavr 1.6 counts a parity bit in every UART byte (11 bits for 8N1); true corrects the
        /// byte time to the real 10 bits once the firmware has set the baud rate.
        bool fixUartByteTime = true;
    };
    explicit SimBoard(const Options& options);
    ~SimBoard();
    SimBoard(const SimBoard&) = delete;
    SimBoard& operator=(const SimBoard&) = delete;

    static constexpr double kClockHz = 16e6;
    double now() const;                       ///< s of simulated time since power-on
    std::uint64_t cycle() const;
    /// Runs the CPU until simulated time t (rounded up to a whole cycle). Throws std::runtime_error
    /// if the firmware crashes.
    void runUntil(double t);
    void runUntilCycle(std::uint64_t cycle);

    /// Host → board: the bytes enter UART0's receiver now; simavr delivers one per byte time.
    void send(const std::uint8_t* bytes, std::size_t n);
    struct RxByte { double t; std::uint64_t cycle; std::uint8_t b; };   ///< t, cycle = end of the byte's stop bit
    std::deque<RxByte>& received() { return rx_; }
    /// Board → host corruption on the wire: the byte with this index (counted from power-on) is
    /// xor-ed with `mask` before the host sees it.
    void corruptTxByte(std::uint64_t index, std::uint8_t mask) { corruptIndex_ = index; corruptMask_ = mask; }
    std::uint64_t txCount() const { return txCount_; }
    /// s per byte on the simulated wire (after the parity correction).
    double byteTime() const;
    double baud() const;                      ///< the rate the firmware configured, 8N1 bits/s

    // PWM pins of motors 1..9 (index 0..8).
    /// Starts a new duty window on every pin.
    void markDutyWindow();
    /// High time / window length since markDutyWindow().
    double duty(int motor) const;
    /// s: the last time pin `motor` was high (now() while it is high; −1 never).
    double lastHigh(int motor) const;
    std::uint64_t edges(int motor) const { return pins_[static_cast<std::size_t>(motor)].edges; }

    Mpu9250Model& imu() { return *imu_; }
    avr_t* avr() { return avr_; }
    std::uint64_t instructions() const { return steps_; }

private:
    struct Pin {
        int state = 0;
        std::uint64_t lastEdge = 0, windowStart = 0, highCycles = 0, edges = 0;
        std::uint64_t lastHighEnd = 0;
        bool everHigh = false;
    };
    static void onUartOut(avr_irq_t* irq, std::uint32_t value, void* param);
    static void onTwiOut(avr_irq_t* irq, std::uint32_t value, void* param);
    static void onPin(avr_irq_t* irq, std::uint32_t value, void* param);
    void fixByteTime();

    Options options_;
    avr_t* avr_ = nullptr;
    avr_irq_t* uartIn_ = nullptr;
    avr_irq_t* twiIn_ = nullptr;
    void* uart_ = nullptr;                    ///< avr_uart_t* of UART0
    std::unique_ptr<Mpu9250Model> imu_;
    std::deque<RxByte> rx_;
    std::array<Pin, 9> pins_ {};
    struct PinHook { SimBoard* board; int motor; };
    std::array<PinHook, 9> hooks_ {};
    std::uint64_t steps_ = 0;
    std::uint64_t txCount_ = 0, corruptIndex_ = ~0ull;
    std::uint8_t corruptMask_ = 0;
    bool fixed_ = false;
};

/// The firmware image the build made (CMake passes its path), or "" when not built.
std::string firmwareElf();

} // namespace armadillo::firmware_test
