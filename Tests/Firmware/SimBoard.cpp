#include "SimBoard.h"

extern "C" {
#include <avr_ioport.h>
#include <avr_twi.h>
#include <avr_uart.h>
#include <sim_avr.h>
#include <sim_elf.h>
}
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

using namespace armadillo;

namespace armadillo::firmware_test {

namespace {
constexpr double kG = 9.80665;
constexpr double kRadToDeg = 57.29577951308232;

std::int16_t clamp16(double v)
{
    const double r = std::round(v);
    return static_cast<std::int16_t>(std::clamp(r, -32768.0, 32767.0));
}
void putBe(std::uint8_t* p, std::int16_t v) { p[0] = static_cast<std::uint8_t>(static_cast<std::uint16_t>(v) >> 8); p[1] = static_cast<std::uint8_t>(v & 0xFF); }
void putLe(std::uint8_t* p, std::int16_t v) { p[1] = static_cast<std::uint8_t>(static_cast<std::uint16_t>(v) >> 8); p[0] = static_cast<std::uint8_t>(v & 0xFF); }

void noSleep(avr_t*, avr_cycle_count_t) {}
constexpr avr_io_addr_t kTwcr = 0xBC;   // ATmega2560 TWCR (data-space address)   // run as fast as the host can: time is simulated
} // namespace

std::string firmwareElf()
{
#ifdef ARMADILLO_FIRMWARE_ELF
    return ARMADILLO_FIRMWARE_ELF;
#else
    return {};
#endif
}

// ---- MPU-9250 + AK8963 ----------------------------------------------------------------------------

Mpu9250Model::Mpu9250Model(std::shared_ptr<const link::MotionSource> motion, const link::SensorModelParams& params)
    : motion_(std::move(motion)), model_(params)
{
    mpu_.fill(0);
    mpu_[0x6B] = 0x01;
    mpu_[0x75] = 0x71;   // WHO_AM_I
    ak_.fill(0);
    ak_[0x00] = 0x48;    // WIA
}

void Mpu9250Model::sampleMpu(double t)
{
    if (t != lastSample_) {
        model_.sample(motion_->at(t), t, motors);
        truth_ = model_.lastTruth();
        lastSample_ = t;
    }
    const int afs = (mpu_[0x1C] >> 3) & 3, gfs = (mpu_[0x1B] >> 3) & 3;
    const double lsbPerG = 16384.0 / (1 << afs);
    const double lsbPerDps = 131.0 / (1 << gfs);
    // Device (x, y, z) = MPU (x, z, −y)  ⇒  MPU (x, y, z) = device (x, −z, y).
    const Eigen::Vector3d a = truth_.accel / kG * lsbPerG;
    const Eigen::Vector3d w = truth_.gyro * kRadToDeg * lsbPerDps;
    const double ax[3] = {a.x(), -a.z(), a.y()};
    const double gx[3] = {w.x(), -w.z(), w.y()};
    for (int i = 0; i < 3; ++i) {
        putBe(&mpu_[static_cast<std::size_t>(0x3B + 2 * i)], clamp16(ax[i]));
        putBe(&mpu_[static_cast<std::size_t>(0x43 + 2 * i)], clamp16(gx[i]));
    }
    putBe(&mpu_[0x41], 0);   // temperature: 21 °C
    ++mpuReads;
}

void Mpu9250Model::updateMag(double t)
{
    const int mode = ak_[0x0A] & 0x0F;
    const double period = mode == 0x06 ? 0.01 : (mode == 0x02 ? 0.125 : 0.0);
    if (period <= 0.0 || nextMag_ < 0.0 || t < nextMag_) return;
    while (nextMag_ <= t) nextMag_ += period;
    if (lastSample_ < 0.0) sampleMpu(t);
    // Device (x, y, z) = AK (y, −z, −x)  ⇒  AK (x, y, z) = device (−z, x, −y).
    const Eigen::Vector3d uT = truth_.mag * fieldMicroTesla;
    const double ak[3] = {-uT.z(), uT.x(), -uT.y()};
    const double lsb = (ak_[0x0A] & 0x10) ? 0.15 : 0.6;   // µT per LSB, 16-bit or 14-bit output
    for (int i = 0; i < 3; ++i) {
        const double adj = (asa[static_cast<std::size_t>(i)] + 128.0) / 256.0;   // the chip's own sensitivity
        putLe(&ak_[static_cast<std::size_t>(0x03 + 2 * i)], clamp16(ak[i] / lsb / adj));
    }
    ak_[0x02] |= 0x01;       // ST1.DRDY
    ++magReads;
}

void Mpu9250Model::onTwi(std::uint32_t value, double t, avr_t* avr, avr_irq_t* replyIrq)
{
    avr_twi_msg_irq_t v;
    v.u.v = value;
    const std::uint8_t msg = v.u.twi.msg, addr = v.u.twi.addr, data = v.u.twi.data;
    static const bool trace = std::getenv("SIMBOARD_TRACE_I2C") != nullptr;
    if (trace) std::fprintf(stderr, "i2c t=%.6f msg=%02x addr=%02x data=%02x sel=%d ptr=%02x twsr=%02x\n", t, msg, addr, data, selected_, ptr_, avr->data[0xB9]);
    if (msg & TWI_COND_STOP) selected_ = 0;
    if (msg & TWI_COND_START) {
        selected_ = 0;
        const int a7 = addr >> 1;
        const bool bypass = (mpu_[0x37] & 0x02) != 0;
        if (present && a7 == 0x68) selected_ = 1;
        else if (present && bypass && a7 == 0x0C) selected_ = 2;
        if (selected_) {
            if (!(addr & 1)) havePointer_ = false;       // a write starts with the register pointer
            else if (selected_ == 1) sampleMpu(t);       // a read snapshots the data registers
            else updateMag(t);
            avr_raise_irq(replyIrq, avr_twi_irq_msg(TWI_COND_ACK, addr, 1));
        }
    }
    if (!selected_) return;
    (void)avr;
    if (msg & TWI_COND_WRITE) {
        avr_raise_irq(replyIrq, avr_twi_irq_msg(TWI_COND_ACK, addr, 1));
        if (!havePointer_) {
            ptr_ = data;
            havePointer_ = true;
            return;
        }
        if (selected_ == 1) {
            if (ptr_ == 0x6B && (data & 0x80)) {         // H_RESET: registers to their defaults
                mpu_.fill(0);
                mpu_[0x6B] = 0x01;
                mpu_[0x75] = 0x71;
            } else if (ptr_ < mpu_.size() && ptr_ != 0x75) {
                mpu_[ptr_] = data;
            }
            ptr_ = static_cast<std::uint8_t>((ptr_ + 1) & 0x7F);
        } else {
            if (ptr_ == 0x0A) {
                ak_[0x0A] = data;
                const int mode = data & 0x0F;
                nextMag_ = (mode == 0x06) ? t + 0.01 : (mode == 0x02 ? t + 0.125 : -1.0);
                if (mode == 0x0F) for (int i = 0; i < 3; ++i) ak_[static_cast<std::size_t>(0x10 + i)] = asa[static_cast<std::size_t>(i)];
                else for (int i = 0; i < 3; ++i) ak_[static_cast<std::size_t>(0x10 + i)] = 0;
            }
            ++ptr_;
        }
    }
    if (msg & TWI_COND_READ) {
        std::uint8_t out = 0;
        if (selected_ == 1) {
            out = mpu_[ptr_ & 0x7F];
            ptr_ = static_cast<std::uint8_t>((ptr_ + 1) & 0x7F);
        } else {
            out = ptr_ < ak_.size() ? ak_[ptr_] : 0;
            if (ptr_ == 0x09) ak_[0x02] &= static_cast<std::uint8_t>(~0x01);   // reading ST2 ends the data read
            ++ptr_;
        }
        avr_raise_irq(replyIrq, avr_twi_irq_msg(TWI_COND_READ, addr, out));
    }
}

// ---- The board ------------------------------------------------------------------------------------

SimBoard::SimBoard(const Options& options) : options_(options)
{
    if (options_.elf.empty()) throw std::runtime_error("SimBoard: no firmware .elf (build firmware/ first)");
    elf_firmware_t fw;
    std::memset(&fw, 0, sizeof fw);
    if (elf_read_firmware(options_.elf.c_str(), &fw) != 0)
        throw std::runtime_error("SimBoard: cannot read " + options_.elf);
    avr_ = avr_make_mcu_by_name("atmega2560");
    if (!avr_) throw std::runtime_error("SimBoard: simavr has no atmega2560 core");
    avr_init(avr_);
    avr_->frequency = static_cast<std::uint32_t>(kClockHz);
    avr_load_firmware(avr_, &fw);
    avr_->log = LOG_ERROR;
    avr_->sleep = noSleep;

    std::uint32_t flags = 0;   // no stdio echo, no sleeping while the firmware polls an empty UART
    avr_ioctl(avr_, AVR_IOCTL_UART_SET_FLAGS('0'), &flags);
    uartIn_ = avr_io_getirq(avr_, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_INPUT);
    avr_irq_register_notify(avr_io_getirq(avr_, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUTPUT), onUartOut, this);
    for (avr_io_t* io = avr_->io_port; io; io = io->next)
        if (io->kind && std::strcmp(io->kind, "uart") == 0 && reinterpret_cast<avr_uart_t*>(io)->name == '0') uart_ = io;
    if (!uart_) throw std::runtime_error("SimBoard: UART0 not found");

    imu_ = std::make_unique<Mpu9250Model>(options_.motion, options_.sensors);
    imu_->present = options_.imuPresent;
    twiIn_ = avr_io_getirq(avr_, AVR_IOCTL_TWI_GETIRQ(0), TWI_IRQ_INPUT);
    avr_irq_register_notify(avr_io_getirq(avr_, AVR_IOCTL_TWI_GETIRQ(0), TWI_IRQ_OUTPUT), onTwiOut, this);
    // simavr 1.6 leaves TWINT set when the firmware writes 1 to it (the flag is "sticky" there), so
    // a read whose status arrives 9 µs later looks complete at once. On the chip, writing 1 clears
    // TWINT until the bus operation finishes; this post-write hook restores that.
    avr_register_io_write(avr_, kTwcr, [](avr_t* avr, avr_io_addr_t addr, std::uint8_t v, void*) {
        if (v & 0x80) avr->data[addr] &= static_cast<std::uint8_t>(~0x80);
    }, nullptr);
    if (std::getenv("SIMBOARD_TRACE_I2C"))
        avr_irq_register_notify(avr_io_getirq(avr_, AVR_IOCTL_TWI_GETIRQ(0), TWI_IRQ_STATUS),
            [](avr_irq_t*, std::uint32_t v, void* param) {
                auto* b = static_cast<SimBoard*>(param);
                std::fprintf(stderr, "i2c t=%.6f status %02x twcr=%02x\n", b->now(), v, b->avr_->data[0xBC]);
            }, this);

    const char ports[9] = {'E', 'E', 'E', 'H', 'H', 'H', 'L', 'L', 'L'};
    const int bits[9] = {3, 4, 5, 3, 4, 5, 3, 4, 5};
    for (int m = 0; m < 9; ++m) {
        hooks_[static_cast<std::size_t>(m)] = {this, m};
        avr_irq_t* irq = avr_io_getirq(avr_, AVR_IOCTL_IOPORT_GETIRQ(ports[m]), bits[m]);
        if (!irq) throw std::runtime_error("SimBoard: no pin IRQ");
        avr_irq_register_notify(irq, onPin, &hooks_[static_cast<std::size_t>(m)]);
    }
}

SimBoard::~SimBoard()
{
    if (avr_) avr_terminate(avr_);
}

double SimBoard::now() const { return static_cast<double>(avr_->cycle) / kClockHz; }
std::uint64_t SimBoard::cycle() const { return avr_->cycle; }

void SimBoard::fixByteTime()
{
    auto* u = static_cast<avr_uart_t*>(uart_);
    // Before the firmware sets the rate simavr uses 100 µs (1600 cycles); after, 11 bit times.
    if (u->cycles_per_byte != 1600 && u->cycles_per_byte % 11 == 0) {
        if (options_.fixUartByteTime) u->cycles_per_byte = u->cycles_per_byte / 11 * 10;
        fixed_ = true;
    }
}

double SimBoard::byteTime() const { return static_cast<double>(static_cast<avr_uart_t*>(uart_)->cycles_per_byte) / kClockHz; }
double SimBoard::baud() const { return 10.0 / byteTime(); }

void SimBoard::runUntil(double t)
{
    runUntilCycle(static_cast<std::uint64_t>(std::ceil(t * kClockHz)));
}

void SimBoard::runUntilCycle(std::uint64_t target)
{
    while (avr_->cycle < target) {
        const int state = avr_run(avr_);
        ++steps_;
        if (state == cpu_Done || state == cpu_Crashed)
            throw std::runtime_error("SimBoard: the firmware stopped (state " + std::to_string(state) + ")");
        if (!fixed_) fixByteTime();
    }
}

void SimBoard::send(const std::uint8_t* bytes, std::size_t n)
{
    for (std::size_t i = 0; i < n; ++i) avr_raise_irq(uartIn_, bytes[i]);
}

void SimBoard::onUartOut(avr_irq_t*, std::uint32_t value, void* param)
{
    auto* self = static_cast<SimBoard*>(param);
    // simavr raises the byte when UDR is written, i.e. when its start bit leaves; the host has it
    // when its stop bit has arrived.
    const std::uint64_t end = self->avr_->cycle + static_cast<avr_uart_t*>(self->uart_)->cycles_per_byte;
    std::uint8_t b = static_cast<std::uint8_t>(value);
    if (self->txCount_++ == self->corruptIndex_) b ^= self->corruptMask_;
    self->rx_.push_back({static_cast<double>(end) / kClockHz, end, b});
}

void SimBoard::onTwiOut(avr_irq_t*, std::uint32_t value, void* param)
{
    auto* self = static_cast<SimBoard*>(param);
    self->imu_->onTwi(value, self->now(), self->avr_, self->twiIn_);
}

void SimBoard::onPin(avr_irq_t*, std::uint32_t value, void* param)
{
    auto* hook = static_cast<PinHook*>(param);
    Pin& p = hook->board->pins_[static_cast<std::size_t>(hook->motor)];
    const int v = value ? 1 : 0;
    if (v == p.state) return;
    const std::uint64_t now = hook->board->avr_->cycle;
    if (p.state) {
        p.highCycles += now - std::max(p.lastEdge, p.windowStart);
        p.lastHighEnd = now;
    } else {
        p.everHigh = true;
    }
    p.state = v;
    p.lastEdge = now;
    ++p.edges;
}

void SimBoard::markDutyWindow()
{
    for (Pin& p : pins_) {
        p.windowStart = avr_->cycle;
        p.highCycles = 0;
    }
}

double SimBoard::duty(int motor) const
{
    const Pin& p = pins_[static_cast<std::size_t>(motor)];
    const std::uint64_t now = avr_->cycle;
    if (now <= p.windowStart) return 0.0;
    std::uint64_t high = p.highCycles;
    if (p.state) high += now - std::max(p.lastEdge, p.windowStart);
    return static_cast<double>(high) / static_cast<double>(now - p.windowStart);
}

double SimBoard::lastHigh(int motor) const
{
    const Pin& p = pins_[static_cast<std::size_t>(motor)];
    if (p.state) return now();
    return p.everHigh ? static_cast<double>(p.lastHighEnd) / kClockHz : -1.0;
}

} // namespace armadillo::firmware_test
