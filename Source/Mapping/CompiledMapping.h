#pragma once
// Private to Source/Mapping: a compiled mapping (the MappingSpec with its ranges resolved, its
// addresses pre-expanded and its control-side state preallocated) and the MappingSet's tables.
// Written by the compiler (MappingCompiler.cpp, MappingSet::build, builder thread), read and
// updated by the evaluator (Mapper.cpp, Mapper::process, control side). Not installed, not
// included outside this folder.
#include "Mapping/Mapper.h"
#include "Mapping/Posture.h"
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace armadillo::mapping {

namespace detail {

inline constexpr long kNone = std::numeric_limits<long>::min();
inline constexpr double kInf = std::numeric_limits<double>::infinity();

inline bool periodic(SourceKind k) noexcept
{
    return k == SourceKind::Azimuth || k == SourceKind::Yaw || k == SourceKind::Roll || k == SourceKind::ArmsRoll;
}

inline double wrap360(double d) noexcept
{
    double r = std::fmod(d, 360.0);
    if (r < 0.0) r += 360.0;
    return r >= 360.0 ? 0.0 : r;
}
inline double wrap180(double d) noexcept { return wrap360(d + 180.0) - 180.0; }

/// One-euro filter (Casiez, Roussel & Vogel, "1€ Filter", CHI 2012): a first-order low-pass whose
/// cutoff rises with the (low-passed) speed of the signal.
struct OneEuro {
    double minCutoff = 0.0, beta = 0.0, dCutoff = 1.0;
    bool started = false;
    double x = 0.0, dx = 0.0, lastT = 0.0;

    static double alpha(double cutoffHz, double dt) noexcept
    {
        const double tau = 1.0 / (2.0 * core::kPi * cutoffHz);
        return 1.0 / (1.0 + tau / dt);
    }
    double filter(double v, double t) noexcept
    {
        if (!started) {
            started = true;
            x = v;
            dx = 0.0;
            lastT = t;
            return v;
        }
        double dt = t - lastT;
        if (!(dt > 0.0) || dt > 1.0) dt = 0.005;
        lastT = t;
        const double rawDx = (v - x) / dt;
        dx += alpha(dCutoff, dt) * (rawDx - dx);
        const double cutoff = minCutoff + beta * std::fabs(dx);
        x += alpha(cutoff, dt) * (v - x);
        return x;
    }
};

struct Sounding {
    bool on = false;
    std::uint8_t channel = 0;   // 0…15
    std::uint8_t note = 0;
    double offAt = kInf;
};

struct Compiled {
    MappingSpec spec;
    double inLo = 0.0, inHi = 1.0, outLo = 0.0, outHi = 1.0, hysteresis = 3.0;
    bool isPeriodic = false;
    int scale = 0;                     // scaleMask, 0 = none
    int posture = -1;                  // Posture source: classifier index
    bool gestureAny = false, gestureOther = false;
    int oscTarget = 0;
    int param = -1;                    // SceneParam: index into sceneParamIds
    std::vector<std::string> addresses;   // OSC: one per zone (or one); MQTT: the topics likewise
    std::vector<MqttPayloadPart> payload;  // MQTT: the payload template's pieces
    std::array<char, MqttMessage::kMaxPayload> lastPayload {};
    std::uint16_t lastPayloadSize = 0;
    bool eventDriven = false;          // gesture, posture, threshold (not zones)
    int index = 0;                     // in the document
    bool stage = false;                // a Stage destination

    // control-side state
    OneEuro smooth;
    bool haveRaw = false;
    double lastRaw = 0.0, unwrapped = 0.0;
    long lastEncoded = kNone;
    std::array<long, 3> lastAux {kNone, kNone, kNone};   // MPE bend, pressure, timbre
    std::array<std::uint8_t, kOscPacketCapacity> lastOsc {};
    std::uint16_t lastOscSize = 0;
    int zone = -1;
    bool on = false;
    Sounding note;
    int mpeNext = 0;
    bool mpeAnnounced = false;
    bool wasMuted = false;
    // Stage destinations: the first reading only learns where the source is (a threshold already
    // passed or a zone already entered when the set is loaded does not fire); then only a rising
    // edge does. Kept through allNotesOff/panic, so a source still held then does not fire again.
    bool primed = false;

    // any thread
    std::atomic<bool> muted {false};
    std::atomic<float> meter {std::numeric_limits<float>::quiet_NaN()};
    std::atomic<bool> active {false};

    void forget() noexcept
    {
        lastEncoded = kNone;
        lastAux = {kNone, kNone, kNone};
        lastOscSize = 0;
        lastPayloadSize = 0;
        zone = -1;
        on = false;
    }
};

} // namespace detail

struct MappingSet::Impl {
    MappingDocument doc;
    std::unique_ptr<detail::Compiled[]> maps;
    std::size_t count = 0;
    std::vector<OscTarget> targets {OscTarget {}};
    std::vector<std::string> params;
    std::vector<std::string> namedGestures;
    std::uint32_t macros = 0;
    PostureClassifier postures;
    bool hasPostures = false;
};

} // namespace armadillo::mapping
