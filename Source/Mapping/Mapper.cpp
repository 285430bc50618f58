// The mapping evaluator: Mapper runs the active compiled set once per control update (REAL-TIME:
// no allocation, lock, I/O or throw) and takes new sets over through the one hand-over
// (Core/Handover.h). The sets themselves are made by MappingCompiler.cpp.
#include "Mapping/CompiledMapping.h"
#include "Core/Handover.h"
#include "Core/Pose.h"
#include "Osc/Osc.h"
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>

namespace armadillo::mapping {

using namespace detail;

void MappingOutput::clear() noexcept
{
    midiCount = 0;
    oscCount = 0;
    mqttCount = 0;
    paramCount = 0;
    stageCount = 0;
    macroChanged = 0;
    dropped = 0;
    forwardChanged = false;
}

// ---------------------------------------------------------------------------------------------

double readSource(const SourceSpec& source, const MappingInput& in, double forwardDeg) noexcept
{
    switch (source.kind) {
    case SourceKind::ScenePitch: return std::isfinite(in.scene.pitch) ? static_cast<double>(in.scene.pitch) : core::kNaN;
    case SourceKind::SceneFret: return std::isfinite(in.scene.fret) ? static_cast<double>(in.scene.fret) : core::kNaN;
    case SourceKind::SceneStrike: return std::isfinite(in.scene.strike) ? static_cast<double>(in.scene.strike) : core::kNaN;
    case SourceKind::PanelKnob: return std::isfinite(in.scene.panelKnob) ? static_cast<double>(in.scene.panelKnob) : core::kNaN;
    case SourceKind::PanelLevel: return std::isfinite(in.scene.panelLevel) ? static_cast<double>(in.scene.panelLevel) : core::kNaN;
    case SourceKind::PanelSelected: return std::isfinite(in.scene.panelSelected) ? static_cast<double>(in.scene.panelSelected) : core::kNaN;
    case SourceKind::Gesture:
    case SourceKind::Posture:
    case SourceKind::GestureValue: return core::kNaN;
    case SourceKind::ArmsAngle:
    case SourceKind::ArmsRoll:
    case SourceKind::ArmsRaised: {   // both arms, or no value
        const core::ArmState* r = in.arm[0];
        const core::ArmState* l = in.arm[1];
        if (r == nullptr || l == nullptr || !r->valid || !l->valid) return core::kNaN;
        if (source.kind == SourceKind::ArmsRaised) return std::min(r->features.pose.elevationDeg, l->features.pose.elevationDeg);
        if (source.kind == SourceKind::ArmsRoll) return wrap180(l->features.pose.rollDeg - r->features.pose.rollDeg);
        // The forearm axis is device x in earth (INTERFACES.md "Pose"); the angle from the cross and
        // dot products (exact near 0° and 180°, where acos of the dot is not).
        const Eigen::Vector3d a = r->q.normalized() * Eigen::Vector3d::UnitX();
        const Eigen::Vector3d b = l->q.normalized() * Eigen::Vector3d::UnitX();
        return core::radToDeg(std::atan2(a.cross(b).norm(), a.dot(b)));
    }
    default: break;
    }
    if (source.arm < 0 || source.arm >= kMaxArms) return core::kNaN;
    const core::ArmState* arm = in.arm[source.arm];
    if (arm == nullptr || !arm->valid) return core::kNaN;
    const core::Pose& pose = arm->features.pose;
    const double sign = arm->q.w() < 0.0 ? -1.0 : 1.0;
    const double yaw = -wrap180(pose.azimuthDeg - forwardDeg);
    switch (source.kind) {
    case SourceKind::Elevation:
    case SourceKind::Pitch: return pose.elevationDeg;
    case SourceKind::Azimuth: return wrap360(pose.azimuthDeg);
    case SourceKind::Roll: return pose.rollDeg;
    case SourceKind::Yaw: return yaw;
    case SourceKind::QuatW: return sign * arm->q.w();
    case SourceKind::QuatX: return sign * arm->q.x();
    case SourceKind::QuatY: return sign * arm->q.y();
    case SourceKind::QuatZ: return sign * arm->q.z();
    case SourceKind::AngularSpeed: return arm->gyro.allFinite() ? core::radToDeg(arm->gyro.norm()) : core::kNaN;
    case SourceKind::FluxFace: return core::radToDeg(arm->features.fluxFace);
    case SourceKind::FluxEdge: return core::radToDeg(arm->features.fluxEdge);
    case SourceKind::RollTrigger: return arm->features.rollTrigger;
    case SourceKind::Punch: return arm->features.punch;
    case SourceKind::YprQuatW:
    case SourceKind::YprQuatX:
    case SourceKind::YprQuatY:
    case SourceKind::YprQuatZ: {
        // q = qz(yaw)·qy(pitch)·qx(roll), written out (half angles) so nothing is built per call.
        const double a = core::degToRad(yaw) / 2, b = core::degToRad(pose.elevationDeg) / 2, c = core::degToRad(pose.rollDeg) / 2;
        const double ca = std::cos(a), sa = std::sin(a), cb = std::cos(b), sb = std::sin(b), cc = std::cos(c), sc = std::sin(c);
        double w = ca * cb * cc + sa * sb * sc;
        double x = ca * cb * sc - sa * sb * cc;
        double y = ca * sb * cc + sa * cb * sc;
        double z = sa * cb * cc - ca * sb * sc;
        if (w < 0.0) {
            w = -w;
            x = -x;
            y = -y;
            z = -z;
        }
        return source.kind == SourceKind::YprQuatW ? w : source.kind == SourceKind::YprQuatX ? x : source.kind == SourceKind::YprQuatY ? y : z;
    }
    default: return core::kNaN;
    }
}

// ---------------------------------------------------------------------------------------------

struct Mapper::Impl {
    core::Handover<MappingSet> sets; // builder → control side; the replaced set back to be freed
    std::atomic<double> forwardShared {0.0};
    std::atomic<bool> forwardRequest {false};
    std::atomic<std::uint64_t> forwardSerial {0};
    std::uint64_t forwardSeen = 0;
    double forward = 0.0;   // control side

    // ---- output ------------------------------------------------------------------------------
    static void midi(MappingOutput& out, double t, std::uint8_t b0, std::uint8_t b1, std::uint8_t b2, std::uint8_t size) noexcept
    {
        if (out.midiCount >= MappingOutput::kMaxMidi) {
            ++out.dropped;
            return;
        }
        MidiEvent& e = out.midi[static_cast<std::size_t>(out.midiCount++)];
        e.t = t;
        e.size = size;
        e.bytes = {b0, b1, b2};
    }
    static void cc(MappingOutput& out, double t, int channel0, int number, int value) noexcept
    {
        midi(out, t, static_cast<std::uint8_t>(0xB0 | channel0), static_cast<std::uint8_t>(number & 0x7F), static_cast<std::uint8_t>(value & 0x7F), 3);
    }

    static void noteOff(Compiled& c, double t, MappingOutput& out) noexcept
    {
        if (!c.note.on) return;
        midi(out, t, static_cast<std::uint8_t>(0x80 | c.note.channel), c.note.note, 0, 3);
        c.note.on = false;
        c.note.offAt = kInf;
        c.active.store(false, std::memory_order_relaxed);
    }

    static void noteOn(Compiled& c, double t, int channel0, int note, int velocity, double lengthS, MappingOutput& out) noexcept
    {
        noteOff(c, t, out);   // one note per mapping: a retrigger closes the sounding one first
        midi(out, t, static_cast<std::uint8_t>(0x90 | channel0), static_cast<std::uint8_t>(note & 0x7F),
             static_cast<std::uint8_t>(std::clamp(velocity, 1, 127)), 3);
        c.note.on = true;
        c.note.channel = static_cast<std::uint8_t>(channel0);
        c.note.note = static_cast<std::uint8_t>(note & 0x7F);
        c.note.offAt = lengthS > 0.0 ? t + lengthS : kInf;
        c.active.store(true, std::memory_order_relaxed);
    }

    // ---- transform ---------------------------------------------------------------------------
    static double curve(const Compiled& c, double n) noexcept
    {
        const TransformSpec& t = c.spec.transform;
        const double s = t.shape;
        switch (t.curve) {
        case Curve::Linear: return n;
        case Curve::Exp: return std::fabs(s) < 1e-9 ? n : std::expm1(s * n) / std::expm1(s);
        case Curve::Log: return std::fabs(s) < 1e-9 ? n : std::log1p(n * std::expm1(s)) / s;
        case Curve::SCurve: {
            const double k = std::max(0.05, 1.0 + s);
            const double a = std::pow(n, k), b = std::pow(1.0 - n, k);
            return a + b > 0.0 ? a / (a + b) : n;
        }
        case Curve::Table: {
            const auto& tab = t.table;
            if (tab.empty()) return n;
            if (n <= tab.front()[0]) return tab.front()[1];
            for (std::size_t i = 1; i < tab.size(); ++i) {
                if (n <= tab[i][0]) {
                    const double f = (n - tab[i - 1][0]) / (tab[i][0] - tab[i - 1][0]);
                    return tab[i - 1][1] + f * (tab[i][1] - tab[i - 1][1]);
                }
            }
            return tab.back()[1];
        }
        }
        return n;
    }

    /// Source units → normalised 0…1: dead zone, range (clamped), invert, curve, steps.
    static double normalise(const Compiled& c, double x) noexcept
    {
        const TransformSpec& t = c.spec.transform;
        if (t.deadZone > 0.0) {
            const double centre = 0.5 * (c.inLo + c.inHi), half = 0.5 * std::fabs(c.inHi - c.inLo);
            const double d = x - centre;
            if (std::fabs(d) <= t.deadZone) x = centre;
            else if (half > t.deadZone) x = centre + (d - std::copysign(t.deadZone, d)) * half / (half - t.deadZone);
        }
        double n = (x - c.inLo) / (c.inHi - c.inLo);
        n = std::clamp(n, 0.0, 1.0);
        if (t.invert) n = 1.0 - n;
        n = std::clamp(curve(c, n), 0.0, 1.0);
        if (t.steps > 1) n = std::round(n * (t.steps - 1)) / (t.steps - 1);
        return n;
    }

    /// Normalised → the destination's unit (out range), then the musical scale.
    static double scaleOut(const Compiled& c, double n) noexcept
    {
        double v = c.outLo + n * (c.outHi - c.outLo);
        if (c.scale != 0) {
            const int root = c.spec.transform.scaleRoot;
            const double base = std::round(v);
            double best = base;
            for (int d = 0; d <= 12; ++d) {   // nearest scale degree; ties go down
                const int below = static_cast<int>(base) - d, above = static_cast<int>(base) + d;
                if ((c.scale >> (((below - root) % 12 + 12) % 12)) & 1) { best = below; break; }
                if ((c.scale >> (((above - root) % 12 + 12) % 12)) & 1) { best = above; break; }
            }
            v = best;
        }
        return v;
    }

    /// Raw source value → the value zones, thresholds and the range see: forward, |x|, smoothing.
    static double prepare(Compiled& c, double raw, double t, double forward) noexcept
    {
        const TransformSpec& tr = c.spec.transform;
        double x = raw;
        if (tr.forward) x = wrap360(x - forward);
        if (tr.abs) x = std::fabs(x);
        if (tr.minCutoffHz > 0.0) {
            if (c.isPeriodic) {
                c.unwrapped = c.haveRaw ? c.unwrapped + wrap180(x - c.lastRaw) : x;
                c.lastRaw = x;
                c.haveRaw = true;
                const double f = c.smooth.filter(c.unwrapped, t);
                x = c.spec.source.kind == SourceKind::Azimuth ? wrap360(f) : wrap180(f);
            } else {
                x = c.smooth.filter(x, t);
            }
        }
        return x;
    }

    static double auxValue(const AuxSpec& a, const MappingInput& in, double forward, double eventValue) noexcept
    {
        double raw = a.source.kind == SourceKind::GestureValue ? eventValue : readSource(a.source, in, forward);
        if (!std::isfinite(raw)) return 0.5;
        if (a.abs) raw = std::fabs(raw);
        return std::clamp((raw - a.lo) / (a.hi - a.lo), 0.0, 1.0);
    }

    static int velocity(const Compiled& c, const MappingInput& in, double forward, double eventValue) noexcept
    {
        const DestinationSpec& d = c.spec.to;
        if (!d.velocitySource.used) return d.velocity;
        const double n = auxValue(d.velocitySource, in, forward, eventValue);
        return std::clamp(static_cast<int>(std::lround(n * 127.0)), 1, 127);
    }

    // ---- zones -------------------------------------------------------------------------------
    static bool insideZone(const Compiled& c, const ZoneSpec& z, double x, double el, double h) noexcept
    {
        bool ok;
        if (c.isPeriodic) {
            double width = z.to - z.from;
            if (width <= 0.0) width += 360.0;
            width += 2.0 * h;
            ok = width >= 360.0 || wrap360(x - (z.from - h)) < width;
        } else {
            const double lo = std::min(z.from, z.to), hi = std::max(z.from, z.to);
            ok = x >= lo - h && x <= hi + h;
        }
        if (ok && z.hasElevation) ok = std::isfinite(el) && el >= z.elFrom - h && el <= z.elTo + h;
        return ok;
    }

    static int zoneFor(const Compiled& c, double x, double el) noexcept
    {
        const auto& zones = c.spec.zones;
        if (c.zone >= 0 && insideZone(c, zones[static_cast<std::size_t>(c.zone)], x, el, c.hysteresis)) return c.zone;
        for (std::size_t i = 0; i < zones.size(); ++i)
            if (insideZone(c, zones[i], x, el, 0.0)) return static_cast<int>(i);
        return -1;
    }

    // ---- destinations ------------------------------------------------------------------------
    /// A continuous value (v in the destination's unit, n normalised) to its destination, sent
    /// only when its encoding changes.
    void sendValue(Compiled& c, double t, double v, double n, double zoneValue, bool on, const MappingInput& in, MappingOutput& out) noexcept
    {
        c.meter.store(static_cast<float>(n), std::memory_order_relaxed);
        const DestinationSpec& d = c.spec.to;
        const int ch = d.channel - 1;
        const auto changed = [&](long enc) {
            if (enc == c.lastEncoded) return false;
            c.lastEncoded = enc;
            return true;
        };
        switch (d.kind) {
        case DestinationKind::Cc7: {
            const long e = std::clamp(std::lround(v), 0L, 127L);
            if (changed(e)) cc(out, t, ch, d.number, static_cast<int>(e));
            return;
        }
        case DestinationKind::Cc14: {
            const long e = std::clamp(std::lround(v), 0L, 16383L);
            if (!changed(e)) return;
            const int msb = static_cast<int>(e >> 7), lsb = static_cast<int>(e & 0x7F);
            if (d.lsbFirst) {
                cc(out, t, ch, d.number + 32, lsb);
                cc(out, t, ch, d.number, msb);
            } else {
                cc(out, t, ch, d.number, msb);
                cc(out, t, ch, d.number + 32, lsb);
            }
            return;
        }
        case DestinationKind::Nrpn: {
            const long e = std::clamp(std::lround(v), 0L, 16383L);
            if (!changed(e)) return;
            cc(out, t, ch, 99, d.number >> 7);
            cc(out, t, ch, 98, d.number & 0x7F);
            cc(out, t, ch, 6, static_cast<int>(e >> 7));
            cc(out, t, ch, 38, static_cast<int>(e & 0x7F));
            return;
        }
        case DestinationKind::PitchBend: {
            const long e = std::clamp(std::lround(v), 0L, 16383L);
            if (changed(e))
                midi(out, t, static_cast<std::uint8_t>(0xE0 | ch), static_cast<std::uint8_t>(e & 0x7F), static_cast<std::uint8_t>(e >> 7), 3);
            return;
        }
        case DestinationKind::ChannelPressure: {
            const long e = std::clamp(std::lround(v), 0L, 127L);
            if (changed(e)) midi(out, t, static_cast<std::uint8_t>(0xD0 | ch), static_cast<std::uint8_t>(e), 0, 2);
            return;
        }
        case DestinationKind::ProgramChange: {
            const long e = std::clamp(std::lround(v), 0L, 127L);
            if (changed(e)) midi(out, t, static_cast<std::uint8_t>(0xC0 | ch), static_cast<std::uint8_t>(e), 0, 2);
            return;
        }
        case DestinationKind::Macro: {
            const float f = static_cast<float>(std::clamp(v, 0.0, 1.0));
            long bits = 0;
            std::memcpy(&bits, &f, sizeof f);
            if (!changed(bits)) return;
            const int k = d.number - 1;
            out.macro[static_cast<std::size_t>(k)] = f;
            out.macroChanged |= 1u << k;
            return;
        }
        case DestinationKind::SceneParam: {
            const float f = static_cast<float>(c.spec.transform.hasOut ? v : std::clamp(v, 0.0, 1.0));
            long bits = 0;
            std::memcpy(&bits, &f, sizeof f);
            if (!changed(bits)) return;
            if (out.paramCount >= MappingOutput::kMaxParams) {
                ++out.dropped;
                return;
            }
            out.params[static_cast<std::size_t>(out.paramCount++)] = {c.param, f, !c.spec.transform.hasOut};
            return;
        }
        case DestinationKind::Osc: sendOsc(c, t, v, zoneValue, on, in, out, true); return;
        case DestinationKind::Mqtt: sendMqtt(c, t, v, zoneValue, on, out, true); return;
        default: return;   // notes, MPE, forward: events only
        }
    }

    void sendOsc(Compiled& c, double t, double v, double zoneValue, bool on, const MappingInput& in, MappingOutput& out, bool onlyChanges) noexcept
    {
        if (out.oscCount >= MappingOutput::kMaxOsc) {
            ++out.dropped;
            return;
        }
        const DestinationSpec& d = c.spec.to;
        osc::OscArg args[kMaxOscArgs];
        std::size_t argc = 0;
        if (d.args.empty()) {
            args[argc++] = osc::OscArg::float32(static_cast<float>(v));
        } else {
            for (const OscArgSpec& a : d.args) {
                if (argc >= static_cast<std::size_t>(kMaxOscArgs)) break;
                if (a.kind == OscArgSpec::Kind::String) {
                    args[argc++] = osc::OscArg::string(a.text);
                    continue;
                }
                double x = 0.0;
                switch (a.kind) {
                case OscArgSpec::Kind::Number: x = a.number; break;
                case OscArgSpec::Kind::Value: x = v; break;
                case OscArgSpec::Kind::Zone: x = zoneValue; break;
                case OscArgSpec::Kind::On: x = on ? 1.0 : 0.0; break;
                case OscArgSpec::Kind::Source: x = readSource(a.source, in, forward); break;
                default: break;
                }
                if (!std::isfinite(x)) x = 0.0;
                if (a.negate) x = -x;
                if (a.type == 'i') args[argc++] = osc::OscArg::int32(static_cast<std::int32_t>(std::clamp(std::lround(x), -2147483647L, 2147483647L)));
                else if (a.type == 'd') args[argc++] = osc::OscArg::float64(x);
                else args[argc++] = osc::OscArg::float32(static_cast<float>(x));
            }
        }
        const std::size_t zi = c.zone >= 0 && static_cast<std::size_t>(c.zone) < c.addresses.size() ? static_cast<std::size_t>(c.zone) : 0;
        if (c.addresses.empty()) return;
        OscPacket& p = out.osc[static_cast<std::size_t>(out.oscCount)];
        const std::size_t size = osc::encodeOscMessage(c.addresses[zi], args, argc, p.bytes.data(), p.bytes.size());
        if (size == 0) {
            ++out.dropped;
            return;
        }
        if (onlyChanges && size == c.lastOscSize && std::memcmp(p.bytes.data(), c.lastOsc.data(), size) == 0) return;
        std::memcpy(c.lastOsc.data(), p.bytes.data(), size);
        c.lastOscSize = static_cast<std::uint16_t>(size);
        p.t = t;
        p.target = c.oscTarget;
        p.size = static_cast<std::uint16_t>(size);
        ++out.oscCount;
    }

    /// An MQTT message from the payload template (no allocation: std::to_chars into the fixed
    /// record); with onlyChanges, nothing when the payload is the one sent last.
    void sendMqtt(Compiled& c, double t, double v, double zoneValue, bool on, MappingOutput& out, bool onlyChanges) noexcept
    {
        if (c.addresses.empty()) return;
        if (out.mqttCount >= MappingOutput::kMaxMqtt) {
            ++out.dropped;
            return;
        }
        MqttMessage& m = out.mqtt[static_cast<std::size_t>(out.mqttCount)];
        char* p = m.payload.data();
        char* const end = p + m.payload.size();
        const auto put = [&](const char* text, std::size_t n) {
            n = std::min<std::size_t>(n, static_cast<std::size_t>(end - p));
            std::memcpy(p, text, n);
            p += n;
        };
        const auto number = [&](double x, bool round) {
            if (!std::isfinite(x)) x = 0.0;
            if (round || x == std::floor(x)) {
                const auto r = std::to_chars(p, end, static_cast<long long>(std::llround(std::clamp(x, -9.0e15, 9.0e15))));
                if (r.ec == std::errc()) p = r.ptr;
            } else {
                const auto r = std::to_chars(p, end, x, std::chars_format::general, 6);
                if (r.ec == std::errc()) p = r.ptr;
            }
        };
        for (const MqttPayloadPart& part : c.payload) {
            put(part.text.data(), part.text.size());
            switch (part.field) {
            case MqttPayloadPart::Field::None: break;
            case MqttPayloadPart::Field::Value: number(v, false); break;
            case MqttPayloadPart::Field::Round: number(v, true); break;
            case MqttPayloadPart::Field::Zone: number(zoneValue, false); break;
            case MqttPayloadPart::Field::On: put(on ? "1" : "0", 1); break;
            case MqttPayloadPart::Field::State: on ? put("ON", 2) : put("OFF", 3); break;
            case MqttPayloadPart::Field::Arm: number(c.spec.source.arm, true); break;
            }
        }
        const auto size = static_cast<std::uint16_t>(p - m.payload.data());
        if (onlyChanges && size == c.lastPayloadSize && std::memcmp(m.payload.data(), c.lastPayload.data(), size) == 0) return;
        std::memcpy(c.lastPayload.data(), m.payload.data(), size);
        c.lastPayloadSize = size;
        const std::size_t zi = c.zone >= 0 && static_cast<std::size_t>(c.zone) < c.addresses.size() ? static_cast<std::size_t>(c.zone) : 0;
        const std::string& topic = c.addresses[zi];
        std::memcpy(m.topic.data(), topic.data(), topic.size());
        m.topicLength = static_cast<std::uint16_t>(topic.size());
        m.payloadLength = size;
        m.t = t;
        m.qos = static_cast<std::uint8_t>(c.spec.to.qos);
        m.retain = c.spec.to.retain;
        m.rate = static_cast<float>(c.spec.to.rate);
        ++out.mqttCount;
    }

    void mpeExpressions(Compiled& c, double t, int ch, const MappingInput& in, MappingOutput& out, bool force) noexcept
    {
        const DestinationSpec& d = c.spec.to;
        const long bend = d.mpeBend.used ? std::clamp(std::lround(auxValue(d.mpeBend, in, forward, 0.0) * 16383.0), 0L, 16383L) : 8192L;
        const long pressure = d.mpePressure.used ? std::clamp(std::lround(auxValue(d.mpePressure, in, forward, 0.0) * 127.0), 0L, 127L) : 0L;
        const long timbre = d.mpeTimbre.used ? std::clamp(std::lround(auxValue(d.mpeTimbre, in, forward, 0.0) * 127.0), 0L, 127L) : 64L;
        if (force || bend != c.lastAux[0])
            midi(out, t, static_cast<std::uint8_t>(0xE0 | ch), static_cast<std::uint8_t>(bend & 0x7F), static_cast<std::uint8_t>(bend >> 7), 3);
        if (force || timbre != c.lastAux[2]) cc(out, t, ch, 74, static_cast<int>(timbre));
        if (force || pressure != c.lastAux[1]) midi(out, t, static_cast<std::uint8_t>(0xD0 | ch), static_cast<std::uint8_t>(pressure), 0, 2);
        c.lastAux = {bend, pressure, timbre};
    }

    /// An event begins: a zone entered (zoneValue = its value), a gesture (eventValue = its
    /// value), a posture entered or a threshold crossed upward.
    void eventOn(Compiled& c, double t, double eventValue, double zoneValue, const MappingInput& in, MappingOutput& out) noexcept
    {
        const DestinationSpec& d = c.spec.to;
        const bool zoned = !c.spec.zones.empty();
        const bool gesture = c.spec.source.kind == SourceKind::Gesture;
        switch (d.kind) {
        case DestinationKind::Notes: {
            const double length = d.lengthMs > 0.0 ? d.lengthMs / 1000.0 : (gesture ? kDefaultGestureNoteMs / 1000.0 : 0.0);
            noteOn(c, t, d.channel - 1, zoned ? static_cast<int>(zoneValue) : d.number, velocity(c, in, forward, eventValue), length, out);
            c.meter.store(1.0f, std::memory_order_relaxed);
            return;
        }
        case DestinationKind::Mpe: {
            const int master = d.channel - 1;
            const int members = std::clamp(d.mpeMembers, 1, 15);
            if (!c.mpeAnnounced) {   // MPE Configuration Message: RPN 6 on the master channel (MPE 1.0 §2.1)
                cc(out, t, master, 101, 0);
                cc(out, t, master, 100, 6);
                cc(out, t, master, 6, members);
                cc(out, t, master, 101, 127);
                cc(out, t, master, 100, 127);
                c.mpeAnnounced = true;
            }
            noteOff(c, t, out);
            const int k = c.mpeNext;
            c.mpeNext = (c.mpeNext + 1) % members;
            const int ch = master == 0 ? 1 + k : 14 - k;   // lower zone: 2…; upper zone: 15 downward
            mpeExpressions(c, t, ch, in, out, true);
            noteOn(c, t, ch, static_cast<int>(zoneValue), velocity(c, in, forward, eventValue), 0.0, out);
            c.meter.store(1.0f, std::memory_order_relaxed);
            return;
        }
        case DestinationKind::SetForward: {
            const core::ArmState* arm = in.arm[0];
            if (arm && arm->valid) {
                forward = wrap360(arm->features.pose.azimuthDeg);
                forwardShared.store(forward, std::memory_order_relaxed);
                out.forwardChanged = true;
            }
            c.active.store(true, std::memory_order_relaxed);
            return;
        }
        case DestinationKind::Stage:
            // Once per rising edge: eventOn runs only as the event begins (a gesture, a zone or
            // posture entered, a threshold crossed upward), never while it is held.
            if (out.stageCount >= MappingOutput::kMaxStage) {
                ++out.dropped;
                return;
            }
            out.stage[static_cast<std::size_t>(out.stageCount++)] = {t, core::StageCommand {d.stage, d.number}, c.index};
            c.active.store(true, std::memory_order_relaxed);
            c.meter.store(1.0f, std::memory_order_relaxed);
            return;
        case DestinationKind::ProgramChange:
            if (zoned) midi(out, t, static_cast<std::uint8_t>(0xC0 | (d.channel - 1)), static_cast<std::uint8_t>(static_cast<int>(zoneValue) & 0x7F), 0, 2);
            else midi(out, t, static_cast<std::uint8_t>(0xC0 | (d.channel - 1)), static_cast<std::uint8_t>(d.number & 0x7F), 0, 2);
            c.active.store(true, std::memory_order_relaxed);
            return;
        case DestinationKind::Osc: {
            const double n = gesture ? normalise(c, eventValue) : 1.0;
            c.meter.store(static_cast<float>(n), std::memory_order_relaxed);
            sendOsc(c, t, scaleOut(c, n), zoned ? zoneValue : eventValue, true, in, out, false);
            c.active.store(true, std::memory_order_relaxed);
            return;
        }
        case DestinationKind::Mqtt: {
            const double n = gesture ? normalise(c, eventValue) : 1.0;
            c.meter.store(static_cast<float>(n), std::memory_order_relaxed);
            sendMqtt(c, t, scaleOut(c, n), zoned ? zoneValue : eventValue, true, out, false);
            c.active.store(true, std::memory_order_relaxed);
            return;
        }
        default: {
            // A value destination: a zone sends its value as it is, a gesture its transformed
            // value, a posture/threshold the top of the out range.
            c.active.store(true, std::memory_order_relaxed);
            if (zoned) {
                const double n = (zoneValue - c.outLo) / (c.outHi - c.outLo);
                sendValue(c, t, zoneValue, std::clamp(n, 0.0, 1.0), zoneValue, true, in, out);
            } else {
                const double n = gesture ? normalise(c, eventValue) : 1.0;
                sendValue(c, t, scaleOut(c, n), n, eventValue, true, in, out);
            }
            return;
        }
        }
    }

    /// An event ends: a zone left, a posture left, a threshold crossed back (gestures have none).
    void eventOff(Compiled& c, double t, double zoneValue, const MappingInput& in, MappingOutput& out) noexcept
    {
        const DestinationSpec& d = c.spec.to;
        c.active.store(false, std::memory_order_relaxed);
        switch (d.kind) {
        case DestinationKind::Notes:
        case DestinationKind::Mpe:
            noteOff(c, t, out);
            c.meter.store(0.0f, std::memory_order_relaxed);
            return;
        case DestinationKind::Osc:
            c.meter.store(0.0f, std::memory_order_relaxed);
            sendOsc(c, t, scaleOut(c, 0.0), zoneValue, false, in, out, false);
            return;
        case DestinationKind::Mqtt:
            c.meter.store(0.0f, std::memory_order_relaxed);
            sendMqtt(c, t, scaleOut(c, 0.0), zoneValue, false, out, false);
            return;
        case DestinationKind::Stage:
            c.meter.store(0.0f, std::memory_order_relaxed);
            return;
        case DestinationKind::SetForward:
        case DestinationKind::ProgramChange: return;
        default:
            if (c.spec.zones.empty()) sendValue(c, t, scaleOut(c, 0.0), 0.0, zoneValue, false, in, out);
            return;
        }
    }

    // ---- one mapping -------------------------------------------------------------------------
    void run(MappingSet::Impl& s, Compiled& c, const MappingInput& in, MappingOutput& out) noexcept
    {
        const double t = in.t;
        if (c.muted.load(std::memory_order_relaxed)) {
            if (!c.wasMuted) {
                noteOff(c, t, out);
                c.forget();
                c.primed = false;   // unmuted: a stage source held meanwhile does not fire
                c.active.store(false, std::memory_order_relaxed);
                c.wasMuted = true;
            }
            return;
        }
        c.wasMuted = false;
        const MappingSpec& m = c.spec;

        if (m.source.kind == SourceKind::Gesture) {
            for (int i = 0; i < in.gestureCount && in.gestures; ++i) {
                const GestureIn& g = in.gestures[i];
                const char* name = g.name ? g.name : "";
                bool match = c.gestureAny;
                if (c.gestureOther) {
                    match = true;
                    for (const std::string& n : s.namedGestures) match = match && std::strcmp(n.c_str(), name) != 0;
                } else if (!match) {
                    match = std::strcmp(m.source.name.c_str(), name) == 0;
                }
                if (match) eventOn(c, t, static_cast<double>(g.value), static_cast<double>(g.value), in, out);
            }
            return;
        }

        if (m.source.kind == SourceKind::Posture) {
            if (!s.hasPostures || c.posture < 0) return;
            const core::ArmState* arm = in.arm[0];
            if (!arm || !arm->valid) return;
            const PostureState& ps = s.postures.state(c.posture);
            const bool eventDest = m.to.kind == DestinationKind::Notes || m.to.kind == DestinationKind::Osc || m.to.kind == DestinationKind::Mqtt ||
                                   m.to.kind == DestinationKind::SetForward || m.to.kind == DestinationKind::ProgramChange ||
                                   m.to.kind == DestinationKind::Stage;
            if (c.stage && !c.primed) {
                c.primed = true;
                c.on = ps.inside;
                c.active.store(c.on, std::memory_order_relaxed);
                return;
            }
            if (eventDest) {
                if (ps.inside && !c.on) {
                    c.on = true;
                    eventOn(c, t, ps.closeness, ps.closeness, in, out);
                } else if (!ps.inside && c.on) {
                    c.on = false;
                    eventOff(c, t, ps.closeness, in, out);
                }
                return;
            }
            const double n = normalise(c, prepare(c, ps.closeness, t, forward));
            sendValue(c, t, scaleOut(c, n), n, ps.closeness, ps.inside, in, out);
            c.active.store(ps.inside, std::memory_order_relaxed);
            return;
        }

        const double raw = readSource(m.source, in, forward);
        if (!std::isfinite(raw)) return;
        const double x = prepare(c, raw, t, forward);

        if (!m.zones.empty()) {
            double el = core::kNaN;
            const core::ArmState* own = in.arm[isArmSource(m.source.kind) ? m.source.arm : 0]; // a sector's elevation: the same arm's
            if (own && own->valid) el = own->features.pose.elevationDeg;
            const int z = zoneFor(c, x, el);
            if (c.stage && !c.primed) {
                c.primed = true;
                c.zone = z;
                c.active.store(z >= 0, std::memory_order_relaxed);
                return;
            }
            if (z != c.zone) {
                const int old = c.zone;
                if (old >= 0) {
                    c.zone = old;   // the leave message goes to the old zone's address
                    eventOff(c, t, m.zones[static_cast<std::size_t>(old)].value, in, out);
                }
                c.zone = z;
                if (z >= 0) eventOn(c, t, x, m.zones[static_cast<std::size_t>(z)].value, in, out);
            } else if (z >= 0 && m.to.kind == DestinationKind::Mpe && c.note.on) {
                mpeExpressions(c, t, c.note.channel, in, out, false);   // per-note expression while it sounds
            }
            return;
        }

        if (m.transform.hasThreshold) {
            if (c.stage && !c.primed) {
                c.primed = true;
                c.on = x >= m.transform.threshold;
                c.active.store(c.on, std::memory_order_relaxed);
                return;
            }
            if (!c.on && x >= m.transform.threshold) {
                c.on = true;
                eventOn(c, t, x, x, in, out);
            } else if (c.on && x < m.transform.threshold - c.hysteresis) {
                c.on = false;
                eventOff(c, t, x, in, out);
            }
            return;
        }

        const double n = normalise(c, x);
        sendValue(c, t, scaleOut(c, n), n, x, true, in, out);
    }

    void dueNoteOffs(MappingSet::Impl& s, double t, MappingOutput& out) noexcept
    {
        for (std::size_t i = 0; i < s.count; ++i) {
            Compiled& c = s.maps[i];
            if (c.note.on && c.note.offAt <= t) noteOff(c, c.note.offAt, out);
        }
    }

    void endAll(MappingSet::Impl& s, double t, MappingOutput& out) noexcept
    {
        for (std::size_t i = 0; i < s.count; ++i) {
            Compiled& c = s.maps[i];
            if (c.note.on) noteOff(c, std::min(t, c.note.offAt), out);
            if (c.stage) continue;   // its edge state stays: a source held through a panic does not fire again
            c.forget();
            c.active.store(false, std::memory_order_relaxed);
        }
    }

    void swapIn(double t, MappingOutput& out) noexcept
    {
        // The old set's sounding notes end before it goes back to the builder to be freed.
        sets.takeOffered([&](MappingSet* old) noexcept {
            if (old != nullptr) endAll(old->impl(), t, out);
        });
    }
};

Mapper::Mapper() : impl_(std::make_unique<Impl>()) {}
Mapper::~Mapper() = default;

bool Mapper::offer(std::unique_ptr<MappingSet>& set) noexcept { return impl_->sets.offer(set); }

bool Mapper::canOffer() const noexcept { return impl_->sets.canOffer(); }

void Mapper::collect() noexcept { impl_->sets.collect(); }

void Mapper::replace(std::unique_ptr<MappingSet> set) noexcept { impl_->sets.replace(std::move(set)); }

MappingSet* Mapper::newest() noexcept { return impl_->sets.newest(); }

MappingSet* Mapper::active() noexcept { return impl_->sets.active(); }

void Mapper::process(const MappingInput& in, MappingOutput& out) noexcept
{
    Impl& m = *impl_;
    m.swapIn(in.t, out);
    const std::uint64_t serial = m.forwardSerial.load(std::memory_order_acquire);
    if (serial != m.forwardSeen) {   // setForwardAzimuth() from another thread
        m.forwardSeen = serial;
        m.forward = m.forwardShared.load(std::memory_order_relaxed);
    }
    const core::ArmState* arm = in.arm[0];
    if (arm && arm->valid && m.forwardRequest.exchange(false, std::memory_order_acq_rel)) {
        m.forward = wrap360(arm->features.pose.azimuthDeg);
        m.forwardShared.store(m.forward, std::memory_order_relaxed);
        out.forwardChanged = true;
    }
    if (m.sets.active() == nullptr) return;
    MappingSet::Impl& s = m.sets.active()->impl();
    m.dueNoteOffs(s, in.t, out);
    if (s.hasPostures && arm && arm->valid)
        s.postures.update(arm->q, arm->gyro.allFinite() ? core::radToDeg(arm->gyro.norm()) : core::kNaN);
    for (std::size_t i = 0; i < s.count; ++i)
        if (!in.stageOnly || s.maps[i].spec.to.kind == DestinationKind::Stage) m.run(s, s.maps[i], in, out);
}

void Mapper::flush(double t, MappingOutput& out) noexcept
{
    if (MappingSet* set = impl_->sets.active()) impl_->dueNoteOffs(set->impl(), t, out);
}

void Mapper::allNotesOff(double t, MappingOutput& out) noexcept
{
    if (MappingSet* set = impl_->sets.active()) impl_->endAll(set->impl(), t, out);
}

void Mapper::resendSceneParams() noexcept
{
    MappingSet* set = impl_->sets.active();
    if (set == nullptr) return;
    MappingSet::Impl& s = set->impl();
    for (std::size_t i = 0; i < s.count; ++i)
        if (s.maps[i].spec.to.kind == DestinationKind::SceneParam) s.maps[i].lastEncoded = kNone;
}

void Mapper::panic(double t, MappingOutput& out) noexcept
{
    allNotesOff(t, out);
    for (int channel = 0; channel < 16; ++channel) {
        Impl::cc(out, t, channel, 120, 0);   // All Sound Off
        Impl::cc(out, t, channel, 123, 0);   // All Notes Off
    }
}

void Mapper::requestForward() noexcept { impl_->forwardRequest.store(true, std::memory_order_release); }

void Mapper::setForwardAzimuth(double deg) noexcept
{
    impl_->forwardShared.store(std::isfinite(deg) ? wrap360(deg) : 0.0, std::memory_order_relaxed);
    impl_->forwardSerial.fetch_add(1, std::memory_order_acq_rel);
}

double Mapper::forwardAzimuth() const noexcept { return impl_->forwardShared.load(std::memory_order_relaxed); }

} // namespace armadillo::mapping
