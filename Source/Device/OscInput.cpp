#include "Device/OscInput.h"
#include "Core/Pose.h"
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace armadillo::device {

std::string oscStatsJson(const OscInputStats& s, const char* format, const std::string& device)
{
    std::string out = "\"format\":\"";
    out += format;
    out += "\",\"device\":\"";
    for (const char c : device)
        if (c != '"' && c != '\\' && static_cast<unsigned char>(c) >= 0x20) out += c;
    out += '"';
    const std::pair<const char*, std::uint64_t> fields[] = {
        {"datagrams", s.datagrams},       {"imu", s.imu},
        {"orientation", s.orientation},   {"tilt_only", s.tiltOnly},
        {"malformed", s.malformed},       {"too_deep", s.tooDeep},
        {"wrong_types", s.wrongTypes},    {"non_finite", s.nonFinite},
        {"absurd", s.absurd},             {"out_of_order", s.outOfOrder},
        {"other_format", s.otherFormat},  {"other_device", s.otherDevice},
        {"device_switches", s.deviceSwitches}, {"flood", s.flood},
        {"incomplete", s.incomplete},     {"unused_orientation", s.unusedOrientation},
        {"clock_resets", s.clockResets},  {"ignored", s.ignored},
        {"compass_field", s.synthesizedField}};
    for (const auto& [k, v] : fields) {
        char buf[64];
        std::snprintf(buf, sizeof buf, ",\"%s\":%llu", k, static_cast<unsigned long long>(v));
        out += buf;
    }
    return out;
}

OscSampleMerger::OscSampleMerger(const OscInputOptions& options) : options_(options)
{
    mountName_.reserve(64);
    if (options_.mountGiven) {
        mountQ_ = options_.mount.rotation.normalized();
        mountName_ = options_.mount.name;
    }
    if (options_.format != OscFormat::Auto) lockFormat(options_.format);
}

void OscSampleMerger::setSinks(ImuSink imu, OrientationSink orientation, void* context) noexcept
{
    imuSink_ = imu;
    orientationSink_ = orientation;
    context_ = context;
}

void OscSampleMerger::lockFormat(OscFormat f) noexcept
{
    if (!options_.mountGiven) {
        Mount m;
        mountPreset(defaultMountPresetForFormat(oscFormatName(f)), m);
        mountQ_ = m.rotation;
        mountName_.assign(m.name.data(), std::min<std::size_t>(m.name.size(), 63));   // capacity reserved: no allocation
    }
    format_.store(f, std::memory_order_release);
}

Mount OscSampleMerger::mount() const
{
    Mount m;
    m.rotation = mountQ_;
    m.name = mountName_;
    return m;
}

std::string OscSampleMerger::deviceName() const
{
    while (nameLock_.exchange(true, std::memory_order_acquire)) {}
    std::string s = deviceName_;
    nameLock_.store(false, std::memory_order_release);
    return s;
}

const char* OscSampleMerger::lastError() const noexcept
{
    const char* e = lastError_.load(std::memory_order_acquire);
    return e ? e : "";
}

OscInputStats OscSampleMerger::stats() const noexcept
{
    OscInputStats s;
    s.datagrams = n_.datagrams.load();
    s.imu = n_.imu.load();
    s.orientation = n_.orientation.load();
    s.ignored = n_.ignored.load();
    s.malformed = n_.malformed.load();
    s.tooDeep = n_.tooDeep.load();
    s.wrongTypes = n_.wrongTypes.load();
    s.nonFinite = n_.nonFinite.load();
    s.absurd = n_.absurd.load();
    s.outOfOrder = n_.outOfOrder.load();
    s.otherFormat = n_.otherFormat.load();
    s.otherDevice = n_.otherDevice.load();
    s.deviceSwitches = n_.deviceSwitches.load();
    s.flood = n_.flood.load();
    s.incomplete = n_.incomplete.load();
    s.unusedOrientation = n_.unusedOrientation.load();
    s.clockResets = n_.clockResets.load();
    s.tiltOnly = n_.tiltOnly.load();
    s.synthesizedField = n_.synthesizedField.load();
    s.bad = s.malformed + s.tooDeep + s.wrongTypes + s.nonFinite + s.absurd;
    return s;
}

void OscSampleMerger::refuse(DecodeStatus s, const char* why) noexcept
{
    switch (s) {
    case DecodeStatus::WrongTypes: n_.wrongTypes.fetch_add(1, std::memory_order_relaxed); break;
    case DecodeStatus::NonFinite: n_.nonFinite.fetch_add(1, std::memory_order_relaxed); break;
    case DecodeStatus::Absurd: n_.absurd.fetch_add(1, std::memory_order_relaxed); break;
    default: break;
    }
    lastError_.store(why ? why : decodeStatusName(s), std::memory_order_release);
}

void OscSampleMerger::handleDatagram(const std::uint8_t* data, std::size_t size, double arrival, std::uint64_t senderKey,
                                     const char* senderName) noexcept
{
    n_.datagrams.fetch_add(1, std::memory_order_relaxed);
    struct Ctx {
        OscSampleMerger* self;
        double arrival;
        std::uint64_t key;
        const char* name;
    } ctx {this, arrival, senderKey, senderName};
    const char* why = nullptr;
    const bool ok = decodeOscPacket(
        data, size, [](void* c, const OscMessage& m) {
            auto* x = static_cast<Ctx*>(c);
            x->self->handleMessage(m, x->arrival, x->key, x->name);
        },
        &ctx, &why);
    if (!ok) {
        // Messages before the fault were delivered; the datagram still counts as malformed.
        if (why && std::strcmp(why, "bundles nested too deeply") == 0) n_.tooDeep.fetch_add(1, std::memory_order_relaxed);
        else n_.malformed.fetch_add(1, std::memory_order_relaxed);
        lastError_.store(why ? why : "malformed OSC packet", std::memory_order_release);
    }
}

double OscSampleMerger::timeOf(const OscMessage& m, double arrival) noexcept
{
    if (m.timeTag <= 1) return arrival;   // "immediately" (or a bare message): the arrival time
    // The sender's clock, anchored to ours at its first tag and then following slowly (time
    // constant ≈ 10⁴ samples) so the intervals stay the sender's own while a drift between the
    // two clocks is absorbed; a jump of more than a second (sender restarted) re-anchors.
    const double tag = oscTimeTagSeconds(m.timeTag);
    const double d = arrival - tag;
    if (!haveOffset_ || std::abs(d - tagOffset_) > 1.0) {
        if (haveOffset_) n_.clockResets.fetch_add(1, std::memory_order_relaxed);
        tagOffset_ = d;
        haveOffset_ = true;
    } else {
        tagOffset_ += 1e-4 * (d - tagOffset_);
    }
    return tag + tagOffset_;
}

bool OscSampleMerger::acceptDevice(const SensorReading& r, double arrival, std::uint64_t senderKey, const char* senderName) noexcept
{
    const std::uint64_t key = r.deviceKey != 0 ? r.deviceKey : senderKey;
    if (key == deviceKey_ && deviceKey_ != 0) {
        deviceLastArrival_ = arrival;
        return true;
    }
    if (deviceKey_ != 0 && arrival - deviceLastArrival_ <= options_.deviceTimeoutSeconds) {
        n_.otherDevice.fetch_add(1, std::memory_order_relaxed);
        lastError_.store("messages from a second device ignored (one device at a time)", std::memory_order_release);
        return false;
    }
    if (deviceKey_ != 0) {
        n_.deviceSwitches.fetch_add(1, std::memory_order_relaxed);
        resetStreams();
    }
    deviceKey_ = key == 0 ? 1 : key;
    deviceLastArrival_ = arrival;
    while (nameLock_.exchange(true, std::memory_order_acquire)) {}
    const char* id = r.device[0] ? r.device : (senderName ? senderName : "");
    std::snprintf(deviceName_, sizeof deviceName_, "%s", id);
    nameLock_.store(false, std::memory_order_release);
    return true;
}

void OscSampleMerger::resetStreams() noexcept
{
    gyro_ = accel_ = gravity_ = user_ = mag_ = heading_ = Held {};
    firstAccelT_ = -1.0;
    streamStart_ = -1.0;
    tiltT_ = -1.0;
    haveOffset_ = false;
}

void OscSampleMerger::handleMessage(const OscMessage& m, double arrival, std::uint64_t senderKey, const char* senderName) noexcept
{
    OscFormat f = format_.load(std::memory_order_relaxed);
    if (f == OscFormat::Auto) {
        const OscFormat d = detectOscFormat(m);
        if (d == OscFormat::Auto) {
            n_.ignored.fetch_add(1, std::memory_order_relaxed);
            return;
        }
        lockFormat(d);
        f = d;
    }
    SensorReading r;
    const char* why = nullptr;
    const DecodeStatus s = decodeOscReading(f, m, r, &why);
    switch (s) {
    case DecodeStatus::Reading: break;
    case DecodeStatus::Known: n_.ignored.fetch_add(1, std::memory_order_relaxed); return;
    case DecodeStatus::NotMine: {
        const OscFormat other = detectOscFormat(m);
        if (other != OscFormat::Auto && other != f) {
            n_.otherFormat.fetch_add(1, std::memory_order_relaxed);
            lastError_.store("messages of another sender app ignored (one format at a time; --osc-format forces one)", std::memory_order_release);
        } else {
            n_.ignored.fetch_add(1, std::memory_order_relaxed);
        }
        return;
    }
    default: refuse(s, why); return;
    }
    if (!acceptDevice(r, arrival, senderKey, senderName)) return;
    onReading(r, timeOf(m, arrival));
}

bool OscSampleMerger::admit(double t) noexcept
{
    if (!(t > lastOut_)) {
        n_.outOfOrder.fetch_add(1, std::memory_order_relaxed);
        return false;
    }
    // The stream's own rate, measured over 1 s windows in which nothing was dropped; a token
    // bucket then lets floodFactor × that rate through (bursts of a quarter second allowed).
    if (windowStart_ < 0.0 || t < windowStart_) {
        windowStart_ = t;
        windowCount_ = 0;
        windowLimited_ = false;
    }
    ++windowCount_;
    if (t - windowStart_ >= 1.0) {
        const double measured = windowCount_ / (t - windowStart_);
        if (!windowLimited_) rateEstimate_ = rateEstimate_ <= 0.0 ? measured : 0.7 * rateEstimate_ + 0.3 * measured;
        windowStart_ = t;
        windowCount_ = 0;
        windowLimited_ = false;
    }
    {
        // Before the first second has measured the stream, a ceiling no real sensor reaches
        // (kOscFloodCeilingHz) holds from the first packet on.
        const double refill = rateEstimate_ > 0.0 ? std::max(options_.floodFactor * rateEstimate_, 20.0) : kOscFloodCeilingHz;
        const double capacity = std::max(0.25 * refill, 10.0);
        if (tokensT_ < 0.0) tokens_ = capacity;
        else tokens_ = std::min(capacity, tokens_ + refill * std::max(0.0, t - tokensT_));
        tokensT_ = t;
        if (tokens_ < 1.0) {
            windowLimited_ = true;
            n_.flood.fetch_add(1, std::memory_order_relaxed);
            lastError_.store("messages arriving far faster than the stream's own rate: dropped (flood)", std::memory_order_release);
            return false;
        }
        tokens_ -= 1.0;
    }
    lastOut_ = t;
    return true;
}

void OscSampleMerger::emitImu(double t, const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel, const Eigen::Vector3d& mag) noexcept
{
    if (!admit(t)) return;
    if (tapOn_.load(std::memory_order_acquire)) {
        SensorFrameSample s;
        s.t = t;
        const Eigen::Quaterniond back = mountQ_.conjugate();
        const Eigen::Vector3d a = back * accel, g = back * gyro;
        for (int i = 0; i < 3; ++i) {
            s.accel[i] = a[i];
            s.gyro[i] = g[i];
        }
        tap_.push(s);
    }
    ImuSample s;
    s.t = t;
    s.gyro = gyro;
    s.accel = accel;
    s.mag = mag;
    n_.imu.fetch_add(1, std::memory_order_relaxed);
    if (imuSink_) imuSink_(context_, s);
}

void OscSampleMerger::emitOrientation(double t, const Eigen::Quaterniond& q, bool tilt) noexcept
{
    if (!admit(t)) return;
    n_.orientation.fetch_add(1, std::memory_order_relaxed);
    if (tilt) n_.tiltOnly.fetch_add(1, std::memory_order_relaxed);
    if (orientationSink_) orientationSink_(context_, t, q);
}

Eigen::Vector3d OscSampleMerger::fieldFromHeading(const Eigen::Vector3d& up) const noexcept
{
    // A compass gives the heading of one device axis; with gravity that fixes where north is in
    // the device frame: the axis's horizontal part, turned back by the heading about "up".
    const Eigen::Vector3d u = up.normalized();
    Eigen::Vector3d h = headingAxis_ - headingAxis_.dot(u) * u;
    if (h.norm() < 0.2) return Eigen::Vector3d(kNaN, kNaN, kNaN);   // that axis is near vertical: no heading
    h.normalize();
    return Eigen::AngleAxisd(degToRad(headingDeg_), u) * h;
}

void OscSampleMerger::onReading(const SensorReading& r, double t) noexcept
{
    using K = SensorReading::Kind;
    const OscFormat f = format_.load(std::memory_order_relaxed);
    const Eigen::Quaterniond& M = mountQ_;
    auto store = [&](Held& h, const Eigen::Vector3d& v) {
        if (t < h.t) {
            n_.outOfOrder.fetch_add(1, std::memory_order_relaxed);
            return false;
        }
        h.v = M * v;
        h.t = t;
        return true;
    };
    auto accelNow = [&](Eigen::Vector3d& a) {
        if (accel_.fresh(t, options_.accelHoldSeconds)) {
            a = accel_.v;
            return true;
        }
        if (gravity_.fresh(t, options_.accelHoldSeconds)) {
            a = gravity_.v + (user_.fresh(t, options_.accelHoldSeconds) ? user_.v : Eigen::Vector3d::Zero());
            return true;
        }
        return false;
    };
    if (streamStart_ < 0.0 || t < streamStart_) streamStart_ = t;
    const bool warming = f != OscFormat::Armadillo && t - streamStart_ < options_.warmupSeconds;
    auto magNow = [&](const Eigen::Vector3d& accel) -> Eigen::Vector3d {
        if (mag_.fresh(t, options_.magHoldSeconds)) return mag_.v;
        if (heading_.fresh(t, options_.magHoldSeconds)) {
            const Eigen::Vector3d m = fieldFromHeading(accel);
            if (m.allFinite()) n_.synthesizedField.fetch_add(1, std::memory_order_relaxed);
            return m;
        }
        return Eigen::Vector3d(kNaN, kNaN, kNaN);
    };

    switch (r.kind) {
    case K::Imu: {
        gyro_.v = M * r.gyro;
        gyro_.t = t;
        const Eigen::Vector3d a = M * r.accel;
        Eigen::Vector3d m = r.mag.allFinite() ? Eigen::Vector3d(M * r.mag) : magNow(a);
        if (!warming) emitImu(t, gyro_.v, a, m);
        return;
    }
    case K::Gyro: {
        if (!store(gyro_, r.gyro)) return;
        Eigen::Vector3d a;
        if (!accelNow(a)) {
            if (!warming) n_.incomplete.fetch_add(1, std::memory_order_relaxed);
            return;
        }
        if (!warming) emitImu(t, gyro_.v, a, magNow(a));
        return;
    }
    case K::Accel:
    case K::Gravity:
    case K::UserAccel: {
        Held& h = r.kind == K::Accel ? accel_ : r.kind == K::Gravity ? gravity_ : user_;
        if (!store(h, r.accel)) return;
        if (r.kind == K::UserAccel) return;   // alone it says nothing about tilt
        if (firstAccelT_ < 0.0) firstAccelT_ = t;
        // No gyroscope at all (or it stopped): the accelerometer alone gives tilt, never heading.
        const bool gyroLive = gyro_.fresh(t, options_.gyroActiveSeconds);
        const bool neverGyro = gyro_.t < -1e299;
        if (gyroLive || warming || (neverGyro && t - firstAccelT_ < 0.3)) return;
        Eigen::Vector3d a;
        if (!accelNow(a) || !(a.norm() > 0.5)) return;
        const Eigen::Vector3d up = a.normalized();
        const double dt = tiltT_ < 0.0 ? 1e9 : std::max(0.0, t - tiltT_);
        const double k = 1.0 - std::exp(-dt / std::max(options_.tiltLowPassSeconds, 1e-6));
        tiltUp_ = tiltT_ < 0.0 ? up : Eigen::Vector3d((tiltUp_ + k * (up - tiltUp_)).normalized());
        tiltT_ = t;
        // Tilt as a pose with the forearm's heading held at north: elevation = asin(up·x),
        // roll = atan2(−up·z, up·y) (INTERFACES.md pose, inverted for "up" in device axes).
        Pose p;
        p.elevationDeg = radToDeg(std::asin(std::clamp(tiltUp_.x(), -1.0, 1.0)));
        p.rollDeg = radToDeg(std::atan2(-tiltUp_.z(), tiltUp_.y()));
        p.azimuthDeg = 0.0;
        emitOrientation(t, poseToQuaternion(p), true);
        return;
    }
    case K::Mag: store(mag_, r.mag); return;
    case K::Heading:
        if (t < heading_.t) return;
        heading_.t = t;
        headingDeg_ = r.headingDeg;
        headingAxis_ = M * r.headingAxis;
        return;
    case K::Orientation: {
        // ARMadillo's own orientation messages are always used (trackers that fuse themselves);
        // a phone's or NGIMU's quaternion only when it sends no gyroscope we can fuse instead.
        if (f != OscFormat::Armadillo && gyro_.fresh(t, options_.gyroActiveSeconds)) {
            n_.unusedOrientation.fetch_add(1, std::memory_order_relaxed);
            return;
        }
        if (warming) return;
        emitOrientation(t, (r.q * M.conjugate()).normalized(), false);
        return;
    }
    case K::None: return;
    }
}

} // namespace armadillo::device
