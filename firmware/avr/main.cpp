// ARMadillo reference firmware: Arduino Mega 2560 (ATmega2560, 16 MHz) + MPU-9250 (I2C) + HC-05 or
// USB serial at 57 600 baud + nine ERM motors on nine hardware PWM pins through a ULN2803.
// docs/HARDWARE.md has the wiring; firmware/README.md how to build and flash.
//
// Structure: the protocol and the safety rules are plain C++ in ../core (unit-tested on the host);
// this file is only the hardware around them.
//  - UART0 receive interrupt: every byte goes through armfw::DeviceLink; when a reply is due the
//    interrupt builds it at once from the latest sample and starts sending it (interrupt-driven
//    transmit), so the board answers within microseconds of a motor packet's last byte and the
//    lock-step link runs at the wire's limit whatever the main loop is doing.
//  - Main loop: reads the MPU-9250 (1 kHz) and the AK8963 (100 Hz) over I2C at 400 kHz, scales
//    them (armfw::toCounts) and publishes the sample; runs armfw::MotorSafety and writes the PWM
//    duties; feeds the hardware watchdog.
//  - Timer0: 1 ms tick. Timer1: 4 µs time base for sample times. Timers 3, 4, 5: motor PWM.
#include <avr/interrupt.h>
#include <avr/io.h>
#include <avr/wdt.h>
#include <util/delay.h>

#include "../core/Protocol.h"
#include "../core/Safety.h"
#include "../core/SensorScale.h"

namespace {

// ---- PWM: nine outputs on the 16-bit timers 3, 4 and 5 ---------------------------------------------
// Fast PWM with TOP = ICRn = 779 at prescaler 1: 16 MHz / 780 = 20.5 kHz — above hearing (ERM motors
// whine audibly at Arduino's default 490 Hz) and slow enough for a ULN2803 (≈ 1 µs turn-off, 2 % of
// the 48.75 µs period). 780 = 15 · 52, so level L (1..14) is OCR = 52·L − 1 and duty (OCR+1)/780 =
// L/15 exactly. Levels 0 and 15 disconnect the compare output and hold the pin low/high (no glitch
// pulse at either end).
constexpr uint16_t kPwmTop = 779;
constexpr uint16_t kPwmStep = 52;

struct PwmPin {
    volatile uint8_t* tccra;
    uint8_t comBit;          // COMnx1 bit in TCCRnA
    volatile uint16_t* ocr;
    volatile uint8_t* port;
    uint8_t bit;
};

// Motor k (1..9, ARMADILLO.md §1: row-major from the wrist row) → pin. Arduino pin numbers in ().
const PwmPin kPins[armfw::kMotors] = {
    {&TCCR3A, COM3A1, &OCR3A, &PORTE, PE3},   // motor 1 (D5)
    {&TCCR3A, COM3B1, &OCR3B, &PORTE, PE4},   // motor 2 (D2)
    {&TCCR3A, COM3C1, &OCR3C, &PORTE, PE5},   // motor 3 (D3)
    {&TCCR4A, COM4A1, &OCR4A, &PORTH, PH3},   // motor 4 (D6)
    {&TCCR4A, COM4B1, &OCR4B, &PORTH, PH4},   // motor 5 (D7)
    {&TCCR4A, COM4C1, &OCR4C, &PORTH, PH5},   // motor 6 (D8)
    {&TCCR5A, COM5A1, &OCR5A, &PORTL, PL3},   // motor 7 (D46)
    {&TCCR5A, COM5B1, &OCR5B, &PORTL, PL4},   // motor 8 (D45)
    {&TCCR5A, COM5C1, &OCR5C, &PORTL, PL5},   // motor 9 (D44)
};

uint8_t g_applied[armfw::kMotors];

void setMotor(uint8_t m, uint8_t level)
{
    const PwmPin& p = kPins[m];
    if (level == 0 || level >= 15) {
        *p.tccra &= static_cast<uint8_t>(~(1u << p.comBit));   // pin follows PORT
        if (level == 0) *p.port &= static_cast<uint8_t>(~(1u << p.bit));
        else *p.port |= static_cast<uint8_t>(1u << p.bit);
    } else {
        *p.ocr = static_cast<uint16_t>(kPwmStep * level - 1);
        *p.port &= static_cast<uint8_t>(~(1u << p.bit));
        *p.tccra |= static_cast<uint8_t>(1u << p.comBit);
    }
    g_applied[m] = level;
}

void pwmInit()
{
    // Outputs low first: from reset until here the pins are inputs and the ULN2803's input
    // resistors keep every motor off (docs/HARDWARE.md).
    PORTE &= static_cast<uint8_t>(~((1 << PE3) | (1 << PE4) | (1 << PE5)));
    PORTH &= static_cast<uint8_t>(~((1 << PH3) | (1 << PH4) | (1 << PH5)));
    PORTL &= static_cast<uint8_t>(~((1 << PL3) | (1 << PL4) | (1 << PL5)));
    DDRE |= (1 << PE3) | (1 << PE4) | (1 << PE5);
    DDRH |= (1 << PH3) | (1 << PH4) | (1 << PH5);
    DDRL |= (1 << PL3) | (1 << PL4) | (1 << PL5);
    // Mode 14 (fast PWM, TOP = ICRn), no prescaler, outputs disconnected until a level asks.
    ICR3 = kPwmTop; ICR4 = kPwmTop; ICR5 = kPwmTop;
    TCCR3A = (1 << WGM31); TCCR3B = (1 << WGM33) | (1 << WGM32) | (1 << CS30);
    TCCR4A = (1 << WGM41); TCCR4B = (1 << WGM43) | (1 << WGM42) | (1 << CS40);
    TCCR5A = (1 << WGM51); TCCR5B = (1 << WGM53) | (1 << WGM52) | (1 << CS50);
    for (uint8_t m = 0; m < armfw::kMotors; ++m) setMotor(m, 0);
}

// ---- Time -----------------------------------------------------------------------------------------
volatile uint32_t g_ms = 0;        // Timer0 CTC, 1 kHz
volatile uint16_t g_t1High = 0;    // Timer1 overflows (4 µs ticks, 262 ms per overflow)

ISR(TIMER0_COMPA_vect) { g_ms = g_ms + 1; }
ISR(TIMER1_OVF_vect) { g_t1High = static_cast<uint16_t>(g_t1High + 1); }

void timeInit()
{
    TCCR0A = (1 << WGM01);                 // CTC
    TCCR0B = (1 << CS01) | (1 << CS00);    // /64 → 250 kHz
    OCR0A = 249;                           // 1 kHz
    TIMSK0 = (1 << OCIE0A);
    TCCR1A = 0;
    TCCR1B = (1 << CS11) | (1 << CS10);    // normal mode, /64 → 4 µs per tick
    TIMSK1 = (1 << TOIE1);
}

uint32_t millisNow()
{
    const uint8_t s = SREG;
    cli();
    const uint32_t v = g_ms;
    SREG = s;
    return v;
}

/// µs since power-up (wraps after 4295 s). Safe with interrupts on or off.
uint32_t microsNow()
{
    const uint8_t s = SREG;
    cli();
    uint16_t low = TCNT1;
    uint16_t high = g_t1High;
    if ((TIFR1 & (1 << TOV1)) && low < 0x8000) ++high;   // overflow pending, not yet counted
    SREG = s;
    return ((static_cast<uint32_t>(high) << 16) | low) * 4u;
}

// ---- Serial link (UART0, 57 600 baud 8N1) -----------------------------------------------------------
armfw::DeviceLink g_link;
armfw::MotorSafety g_safety;
volatile uint16_t g_counts[armfw::kChannels];   // the latest sample, published by the main loop
volatile uint32_t g_sampleUs = 0;
volatile uint8_t g_sensorStatus = 0;
volatile uint16_t g_rateHz = 0;
// Motor packet → main loop hand-over (the interrupt never runs the safety code, so the main loop
// never has to block interrupts for it: a reply is never delayed by the motor bookkeeping).
volatile uint8_t g_newLevels[armfw::kMotors];
volatile uint32_t g_newLevelsMs = 0;
volatile bool g_haveNewLevels = false;
volatile uint8_t g_safetyStatus = 0;            // StatusBits from MotorSafety for the next v2 frame

constexpr uint8_t kTxSize = 64;                  // power of two
volatile uint8_t g_tx[kTxSize];
volatile uint8_t g_txHead = 0, g_txTail = 0;

void uartInit()
{
    UCSR0A = (1 << U2X0);                        // double speed: 16 MHz / (8 · 35) = 57 143 baud (−0.8 %)
    UBRR0H = 0;
    UBRR0L = 34;
    UCSR0C = (1 << UCSZ01) | (1 << UCSZ00);      // 8N1
    UCSR0B = (1 << RXEN0) | (1 << TXEN0) | (1 << RXCIE0);
}

ISR(USART0_RX_vect)
{
    const bool frameError = (UCSR0A & (1 << FE0)) != 0;
    const uint8_t byte = UDR0;
    (void)frameError;   // a framing error still delivers a byte; the protocol's checks reject it
    const uint32_t now = g_ms;
    const armfw::LinkEvent e = g_link.onByte(byte, now);
    if (e == armfw::LinkEvent::Motor) {
        for (uint8_t m = 0; m < armfw::kMotors; ++m) g_newLevels[m] = g_link.levels()[m];
        g_newLevelsMs = now;
        g_haveNewLevels = true;
    }
    if (!g_link.replyDue()) return;
    uint16_t counts[armfw::kChannels];
    for (uint8_t i = 0; i < armfw::kChannels; ++i) counts[i] = g_counts[i];
    uint8_t out[armfw::kV2SensorSize];
    const uint8_t status = static_cast<uint8_t>(g_safetyStatus | g_sensorStatus);
    g_safetyStatus = static_cast<uint8_t>(g_safetyStatus & ~armfw::kStatusWatchdog);   // reported once
    const uint8_t n = g_link.buildReply(counts, g_sampleUs, status, g_rateHz, out, sizeof out);
    for (uint8_t i = 0; i < n; ++i) {
        const uint8_t next = static_cast<uint8_t>((g_txHead + 1) & (kTxSize - 1));
        if (next == g_txTail) break;             // cannot happen in lock-step (≤ 21 bytes in flight)
        g_tx[g_txHead] = out[i];
        g_txHead = next;
    }
    UCSR0B |= (1 << UDRIE0);
}

ISR(USART0_UDRE_vect)
{
    if (g_txHead == g_txTail) {
        UCSR0B &= static_cast<uint8_t>(~(1 << UDRIE0));
        return;
    }
    UDR0 = g_tx[g_txTail];
    g_txTail = static_cast<uint8_t>((g_txTail + 1) & (kTxSize - 1));
}

// ---- I2C (TWI) at 400 kHz, blocking with a bound: a stuck bus is an error, never a hang -------------
constexpr uint8_t kMpuAddr = 0x68;
constexpr uint8_t kMagAddr = 0x0C;

bool twiWait()
{
    for (uint16_t i = 0; i < 2000; ++i)          // ≥ 2000 · 5 cycles ≈ 0.6 ms ≫ one byte (22.5 µs)
        if (TWCR & (1 << TWINT)) return true;
    TWCR = 0;                                    // release the bus and start over next time
    TWCR = (1 << TWEN);
    return false;
}

bool twiStart(uint8_t addrRw)
{
    TWCR = (1 << TWINT) | (1 << TWSTA) | (1 << TWEN);
    if (!twiWait()) return false;
    const uint8_t st = TWSR & 0xF8;
    if (st != 0x08 && st != 0x10) return false;
    TWDR = addrRw;
    TWCR = (1 << TWINT) | (1 << TWEN);
    if (!twiWait()) return false;
    const uint8_t ack = TWSR & 0xF8;
    // SLA+W ACK (0x18) or SLA+R ACK (0x40). simavr 1.6 reports an acknowledged SLA+W as 0x28 (data
    // ACK); a real ATmega2560 never shows 0x28 here, so accepting it changes nothing on hardware.
    return ack == 0x18 || ack == 0x40 || ack == 0x28;
}

void twiStop() { TWCR = (1 << TWINT) | (1 << TWSTO) | (1 << TWEN); }

bool twiWriteByte(uint8_t b)
{
    TWDR = b;
    TWCR = (1 << TWINT) | (1 << TWEN);
    return twiWait() && (TWSR & 0xF8) == 0x28;
}

bool writeReg(uint8_t addr, uint8_t reg, uint8_t value)
{
    const bool ok = twiStart(static_cast<uint8_t>(addr << 1)) && twiWriteByte(reg) && twiWriteByte(value);
    twiStop();
    return ok;
}

/// Register pointer write, STOP, then a read transaction (the MPU-9250 and AK8963 keep the pointer).
bool readRegs(uint8_t addr, uint8_t reg, uint8_t* out, uint8_t n)
{
    bool ok = twiStart(static_cast<uint8_t>(addr << 1)) && twiWriteByte(reg);
    twiStop();
    if (!ok) return false;
    ok = twiStart(static_cast<uint8_t>((addr << 1) | 1));
    for (uint8_t i = 0; ok && i < n; ++i) {
        TWCR = (1 << TWINT) | (1 << TWEN) | (i + 1 < n ? (1 << TWEA) : 0);   // ACK all but the last
        ok = twiWait();
        out[i] = TWDR;
    }
    twiStop();
    return ok;
}

int16_t be16(const uint8_t* p) { return static_cast<int16_t>((static_cast<uint16_t>(p[0]) << 8) | p[1]); }
int16_t le16(const uint8_t* p) { return static_cast<int16_t>((static_cast<uint16_t>(p[1]) << 8) | p[0]); }

int32_t g_magScale[3];

bool imuInit()
{
    TWSR = 0;
    TWBR = 12;                                   // 16 MHz / (16 + 2·12) = 400 kHz
    TWCR = (1 << TWEN);
    uint8_t who = 0;
    if (!writeReg(kMpuAddr, 0x6B, 0x80)) return false;       // PWR_MGMT_1: reset
    _delay_ms(100);
    if (!readRegs(kMpuAddr, 0x75, &who, 1) || (who != 0x71 && who != 0x73)) return false;   // WHO_AM_I (MPU-9250/9255)
    bool ok = writeReg(kMpuAddr, 0x6B, 0x01)                 // clock: PLL
           && writeReg(kMpuAddr, 0x1A, 0x03)                 // CONFIG: gyro DLPF 41 Hz
           && writeReg(kMpuAddr, 0x19, 0x00)                 // SMPLRT_DIV: 1 kHz
           && writeReg(kMpuAddr, 0x1B, 0x10)                 // GYRO_CONFIG: ±1000 °/s
           && writeReg(kMpuAddr, 0x1C, 0x10)                 // ACCEL_CONFIG: ±8 g
           && writeReg(kMpuAddr, 0x1D, 0x03)                 // ACCEL_CONFIG2: DLPF 41 Hz
           && writeReg(kMpuAddr, 0x37, 0x02);                // INT_PIN_CFG: I2C bypass → AK8963 on the bus
    if (!ok) return false;
    uint8_t asa[3] = {128, 128, 128};
    if (!readRegs(kMagAddr, 0x00, &who, 1) || who != 0x48) return false;   // AK8963 WIA
    ok = writeReg(kMagAddr, 0x0A, 0x00);                     // CNTL1: power down
    _delay_ms(10);
    ok = ok && writeReg(kMagAddr, 0x0A, 0x0F);               // fuse ROM access
    _delay_ms(10);
    ok = ok && readRegs(kMagAddr, 0x10, asa, 3);             // ASAX..ASAZ
    ok = ok && writeReg(kMagAddr, 0x0A, 0x00);
    _delay_ms(10);
    ok = ok && writeReg(kMagAddr, 0x0A, 0x16);               // 16-bit, continuous 100 Hz
    armfw::magScales(asa, g_magScale);
    return ok;
}

} // namespace

int main()
{
    MCUSR = 0;
    wdt_disable();
    pwmInit();                                   // motors off before anything else
    timeInit();
    uartInit();
    sei();
    {
        const uint8_t asaDefault[3] = {128, 128, 128};
        armfw::magScales(asaDefault, g_magScale);
    }
    bool imuOk = imuInit();
    wdt_enable(WDTO_120MS);                      // a hung firmware resets, and reset leaves the motors off

    for (uint16_t i = 0; i < armfw::kChannels; ++i) g_counts[i] = 2048;
    armfw::ImuRaw raw = {};
    uint32_t lastImuUs = 0, lastMagMs = 0, rateWindowMs = 0;
    uint16_t reads = 0;

    for (;;) {
        wdt_reset();
        const uint32_t nowUs = microsNow();
        const uint32_t nowMs = millisNow();

        if (!imuOk && nowMs - lastMagMs >= 500) {    // retry a missing/failed IMU twice a second
            lastMagMs = nowMs;
            imuOk = imuInit();
        }
        if (imuOk && nowUs - lastImuUs >= 1000) {   // the MPU-9250 samples at 1 kHz
            // Keep a 1 ms grid (not 1 ms after the last pass), but never try to catch up a backlog.
            lastImuUs = (nowUs - lastImuUs < 3000) ? lastImuUs + 1000 : nowUs;
            uint8_t b[14];
            bool ok = readRegs(kMpuAddr, 0x3B, b, 14);   // ACCEL_XOUT_H .. GYRO_ZOUT_L
            if (ok) {
                for (uint8_t i = 0; i < 3; ++i) {
                    raw.accel[i] = be16(b + 2 * i);
                    raw.gyro[i] = be16(b + 8 + 2 * i);
                }
            }
            if (ok && nowMs - lastMagMs >= 10) {     // the AK8963 at 100 Hz: ST1, data, ST2 (releases the latch)
                uint8_t m[8];
                if (readRegs(kMagAddr, 0x02, m, 8) && (m[0] & 0x01) && !(m[7] & 0x08)) {
                    lastMagMs = nowMs;
                    for (uint8_t i = 0; i < 3; ++i) raw.mag[i] = le16(m + 1 + 2 * i);
                }
            }
            uint16_t counts[armfw::kChannels];
            armfw::toCounts(raw, g_magScale, counts);
            cli();
            for (uint8_t i = 0; i < armfw::kChannels; ++i) g_counts[i] = counts[i];
            g_sampleUs = nowUs;
            g_sensorStatus = ok ? 0 : armfw::kStatusSensorError;
            sei();
            if (ok) ++reads;
        }
        if (nowMs - rateWindowMs >= 1000) {          // the sensor rate the board really sustains
            cli();
            g_rateHz = reads;
            sei();
            reads = 0;
            rateWindowMs = nowMs;
        }

        uint8_t levels[armfw::kMotors], requested[armfw::kMotors];
        bool havePacket = false;
        uint32_t packetMs = 0;
        const uint32_t safetyMs = millisNow();       // after the I2C read: packets may have come in meanwhile
        cli();                                       // a few dozen cycles: copy the hand-over, run the v2 timer
        if (g_haveNewLevels) {
            for (uint8_t m = 0; m < armfw::kMotors; ++m) requested[m] = g_newLevels[m];
            packetMs = g_newLevelsMs;
            g_haveNewLevels = false;
            havePacket = true;
        }
        g_link.tick(safetyMs);
        sei();
        if (havePacket) g_safety.onPacket(requested, packetMs);
        g_safety.output(safetyMs, levels);
        const uint8_t st = g_safety.takeStatus();
        cli();
        g_safetyStatus = static_cast<uint8_t>((g_safetyStatus & armfw::kStatusWatchdog) | st);
        sei();
        for (uint8_t m = 0; m < armfw::kMotors; ++m)
            if (levels[m] != g_applied[m]) setMotor(m, levels[m]);
    }
}
