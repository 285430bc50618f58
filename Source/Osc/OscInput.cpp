#include "Osc/OscInput.h"
#include "Core/Pose.h"
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace armadillo::osc {

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
        {"compass_field", s.synthesizedField}, {"json", s.json}, {"unchanged", s.unchanged}};
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
        link::Mount m;
        mountPreset(link::defaultMountPresetForFormat(oscFormatName(f)), m);
        mountQ_ = m.rotation;
        mountName_.assign(m.name.data(), std::min<std::size_t>(m.name.size(), 63));   // capacity reserved: no allocation
    }
    format_.store(f, std::memory_order_release);
}

link::Mount OscSampleMerger::mount() const
{
    link::Mount m;
    m.rotation = mountQ_;
    m.name = mountName_;
    return m;
}

std::string OscSampleMerger::otherDeviceName() const
{
    while (nameLock_.exchange(true, std::memory_order_acquire)) {}
    std::string s = otherDeviceName_;
    nameLock_.store(false, std::memory_order_release);
    return s;
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
    s.json = n_.json.load();
    s.unchanged = n_.unchanged.load();
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
    noteSender(senderName);
    if (size > 0 && data[0] == '{') {   // ZIG SIM's JSON mode on the same port: told apart by its first byte
        handleJson(data, size, arrival, senderKey, senderName);
        return;
    }
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
        if (size == 0 || (data[0] != '/' && data[0] != '#')) noteJunk(data, size);
    }
}

void OscSampleMerger::handleJson(const std::uint8_t* data, std::size_t size, double arrival, std::uint64_t senderKey,
                                 const char* senderName) noexcept
{
    n_.datagrams.fetch_add(1, std::memory_order_relaxed);
    SensorReading r[6];
    double stamp = core::kNaN;
    const char* why = nullptr;
    const int n = decodeZigSimJson(std::string_view(reinterpret_cast<const char*>(data), size), r, 6, stamp, &why);
    if (n < 0) {
        n_.malformed.fetch_add(1, std::memory_order_relaxed);
        lastError_.store(why ? why : "malformed JSON", std::memory_order_release);
        noteJunk(data, size);
        return;
    }
    n_.json.fetch_add(1, std::memory_order_relaxed);
    OscFormat f = format_.load(std::memory_order_relaxed);
    if (f == OscFormat::Auto) {
        lockFormat(OscFormat::ZigSim);
        f = OscFormat::ZigSim;
    }
    if (f != OscFormat::ZigSim) {
        n_.otherFormat.fetch_add(1, std::memory_order_relaxed);
        lastError_.store("messages of another sender app ignored (one format at a time; --osc-format forces one)", std::memory_order_release);
        return;
    }
    // ZIG SIM's timestamp has millisecond resolution: the sender's clock, anchored like OSC time tags.
    const double t = std::isfinite(stamp) ? senderTime(stamp, arrival) : arrival;
    for (int i = 0; i < n; ++i) {
        if (!acceptDevice(r[i], arrival, senderKey, senderName)) return;
        lastArrival_ = arrival;
        onReading(r[i], t);
    }
}

double OscSampleMerger::timeOf(const OscMessage& m, double arrival) noexcept
{
    if (m.timeTag <= 1) return arrival;   // "immediately" (or a bare message): the arrival time
    return senderTime(oscTimeTagSeconds(m.timeTag), arrival);
}

double OscSampleMerger::senderTime(double tag, double arrival) noexcept
{
    // The sender's clock, anchored to ours at its first tag and then following slowly (time
    // constant ≈ 10⁴ samples) so the intervals stay the sender's own while a drift between the
    // two clocks is absorbed; a jump of more than a second (sender restarted) re-anchors.
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
        while (nameLock_.exchange(true, std::memory_order_acquire)) {}
        std::snprintf(otherDeviceName_, sizeof otherDeviceName_, "%s", r.device[0] ? r.device : (senderName ? senderName : "?"));
        nameLock_.store(false, std::memory_order_release);
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
    headingUsedT_ = -1e300;
    gyroSeen_ = false;
    lastGyroRaw_ = Eigen::Vector3d::Zero();
    for (int i = 0; i < kStreams; ++i) {
        streamLast_[i] = 0.0;
        streamInterval_[i].store(0.0, std::memory_order_relaxed);
    }
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
            noteAddress(m.address);
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
            noteAddress(m.address);
        }
        return;
    }
    default: refuse(s, why); return;
    }
    if (!acceptDevice(r, arrival, senderKey, senderName)) return;
    lastArrival_ = arrival;
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
    lastMade_ = t;
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
    core::ImuSample s;
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
    Eigen::Vector3d h = headingNormal_ ? Eigen::Vector3d(u.cross(headingAxis_)) : Eigen::Vector3d(headingAxis_ - headingAxis_.dot(u) * u);
    if (h.norm() < 0.2) return Eigen::Vector3d(core::kNaN, core::kNaN, core::kNaN); // that axis is near vertical: no heading
    h.normalize();
    return Eigen::AngleAxisd(core::degToRad(headingDeg_), u) * h;
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
    // Sensors2OSC sends a reading only when it differs from the last one of that sensor
    // (SensorConfiguration.sendingNotNeeded): a reading not repeated is unchanged, held until the next.
    const double accelHold = holdsUnchanged() ? 1e300 : options_.accelHoldSeconds;
    const double magHold = holdsUnchanged() ? 1e300 : options_.magHoldSeconds;
    auto accelNow = [&](Eigen::Vector3d& a) {
        if (accel_.fresh(t, accelHold)) {
            a = accel_.v;
            return true;
        }
        if (gravity_.fresh(t, accelHold)) {
            a = gravity_.v + (user_.fresh(t, accelHold) ? user_.v : Eigen::Vector3d::Zero());
            return true;
        }
        return false;
    };
    if (streamStart_ < 0.0 || t < streamStart_) streamStart_ = t;
    const bool warming = f != OscFormat::Armadillo && t - streamStart_ < options_.warmupSeconds;
    auto magNow = [&](const Eigen::Vector3d& accel) -> Eigen::Vector3d {
        if (mag_.fresh(t, magHold)) return mag_.v;
        if (heading_.fresh(t, options_.magHoldSeconds) && heading_.t > headingUsedT_) {
            // One compass reading is one field, made once: held for the next samples it would stay
            // where the arm pointed when it was read (a 10 Hz compass is 0.1 s old by the last one),
            // and the filter would pull the heading back by the turn since.
            // "Up" for it: the sender's own gravity where it separates it (ZIG SIM, GyrOSC), else the
            // accelerometer. The specific force leans with every push of the arm, and the field
            // made from it would turn the heading with the lean.
            const Eigen::Vector3d m = fieldFromHeading(gravity_.fresh(t, accelHold) ? gravity_.v : accel);
            if (m.allFinite()) {
                n_.synthesizedField.fetch_add(1, std::memory_order_relaxed);
                headingUsedT_ = heading_.t;
            }
            return m;
        }
        return Eigen::Vector3d(core::kNaN, core::kNaN, core::kNaN);
    };

    noteRate(static_cast<int>(r.kind), t);
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
        gyroSeen_ = true;
        lastGyroRaw_ = r.gyro;
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
        if (holdsUnchanged() && gyroSeen_ && lastGyroRaw_ == Eigen::Vector3d::Zero()) {
            // Sensors2OSC's gyroscope last said exactly zero and has not changed since: the
            // phone turns by nothing, the accelerometer moved (noise, a push): a whole sample.
            Eigen::Vector3d a;
            if (!warming && accelNow(a)) emitImu(t, Eigen::Vector3d::Zero(), a, magNow(a));
            return;
        }
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
        core::Pose p;
        p.elevationDeg = core::radToDeg(std::asin(std::clamp(tiltUp_.x(), -1.0, 1.0)));
        p.rollDeg = core::radToDeg(std::atan2(-tiltUp_.z(), tiltUp_.y()));
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
        headingNormal_ = r.headingNormalToAxis;
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

bool OscSampleMerger::holdsUnchanged() const noexcept { return format_.load(std::memory_order_relaxed) == OscFormat::Sensors2Osc; }

void OscSampleMerger::tick(double now) noexcept
{
    if (!holdsUnchanged() || deviceKey_ == 0) return;
    // At rest: the gyroscope never sent (all its readings equal the filter's starting zeros) or
    // its last reading was exactly zero. A sender that was turning and went silent is a gap.
    if (gyroSeen_ && lastGyroRaw_ != Eigen::Vector3d::Zero()) return;
    if (streamStart_ < 0.0 || now - streamStart_ < options_.warmupSeconds) return;
    const double period = std::max(options_.restPeriodSeconds, 1e-3);
    if (now - lastMade_ < 0.75 * period || now - lastArrival_ < 1.5 * period) return;
    Eigen::Vector3d a;
    if (accel_.t > -1e299) a = accel_.v;
    else if (gravity_.t > -1e299) a = gravity_.v + (user_.t > -1e299 ? user_.v : Eigen::Vector3d::Zero());
    else return;
    Eigen::Vector3d m(core::kNaN, core::kNaN, core::kNaN);
    if (mag_.t > -1e299) m = mag_.v;
    const std::uint64_t before = n_.imu.load(std::memory_order_relaxed);
    emitImu(now, Eigen::Vector3d::Zero(), a, m);
    if (n_.imu.load(std::memory_order_relaxed) != before) n_.unchanged.fetch_add(1, std::memory_order_relaxed);
}

void OscSampleMerger::noteRate(int stream, double t) noexcept
{
    // SensorReading::Kind order: None, Gyro, Accel, Gravity, UserAccel, Mag, Imu, Orientation, Heading.
    static constexpr int kSlot[] = {-1, 0, 1, 2, 3, 4, 6, 7, 5};
    if (stream < 0 || stream >= static_cast<int>(sizeof kSlot / sizeof kSlot[0]) || kSlot[stream] < 0) return;
    const int i = kSlot[stream];
    const double dt = t - streamLast_[i];
    streamLast_[i] = t;
    if (!(dt > 1e-4 && dt < 2.0)) return;
    const double old = streamInterval_[i].load(std::memory_order_relaxed);
    streamInterval_[i].store(old <= 0.0 ? dt : old + 0.05 * (dt - old), std::memory_order_relaxed);
}

OscSensorRates OscSampleMerger::rates() const noexcept
{
    double r[kStreams];
    for (int i = 0; i < kStreams; ++i) {
        const double dt = streamInterval_[i].load(std::memory_order_relaxed);
        r[i] = dt > 0.0 ? 1.0 / dt : 0.0;
    }
    OscSensorRates o;
    o.gyro = r[0];
    o.accel = r[1];
    o.gravity = r[2];
    o.userAccel = r[3];
    o.mag = r[4];
    o.heading = r[5];
    o.imu = r[6];
    o.orientation = r[7];
    return o;
}

double OscSensorRates::fusion() const noexcept
{
    const double motion = std::max(gyro, imu);
    return motion > 0.0 ? motion : orientation;
}

namespace {
template <std::size_t N>
void copyText(char (&out)[N], std::string_view s) noexcept
{
    const std::size_t n = std::min(s.size(), N - 1);
    std::memcpy(out, s.data(), n);
    out[n] = 0;
}
} // namespace

void OscSampleMerger::noteAddress(std::string_view address) noexcept
{
    while (nameLock_.exchange(true, std::memory_order_acquire)) {}
    for (int i = 0; i < OscHeard::kSlots; ++i) {
        if (heard_.addresses[i][0] == 0) {
            copyText(heard_.addresses[i], address);
            heard_.addressCount[i] = 1;
            break;
        }
        if (std::string_view(heard_.addresses[i]) == address.substr(0, sizeof heard_.addresses[i] - 1)) {
            ++heard_.addressCount[i];
            break;
        }
    }
    nameLock_.store(false, std::memory_order_release);
}

void OscSampleMerger::noteJunk(const std::uint8_t* data, std::size_t size) noexcept
{
    char hex[24] {};
    std::size_t k = 0;
    for (std::size_t i = 0; i < size && i < 7; ++i) k += static_cast<std::size_t>(std::snprintf(hex + k, sizeof hex - k, i ? " %02x" : "%02x", data[i]));
    while (nameLock_.exchange(true, std::memory_order_acquire)) {}
    for (int i = 0; i < OscHeard::kSlots; ++i) {
        if (heard_.junk[i][0] == 0) {
            copyText(heard_.junk[i], hex);
            break;
        }
        if (std::strcmp(heard_.junk[i], hex) == 0) break;
    }
    nameLock_.store(false, std::memory_order_release);
}

void OscSampleMerger::noteSender(const char* name) noexcept
{
    if (!name || !*name) return;
    while (nameLock_.exchange(true, std::memory_order_acquire)) {}
    for (int i = 0; i < OscHeard::kSlots; ++i) {
        if (heard_.senders[i][0] == 0) {
            copyText(heard_.senders[i], name);
            heard_.senderCount[i] = 1;
            break;
        }
        if (std::strcmp(heard_.senders[i], name) == 0) {
            ++heard_.senderCount[i];
            break;
        }
    }
    nameLock_.store(false, std::memory_order_release);
}

OscHeard OscSampleMerger::heard() const
{
    while (nameLock_.exchange(true, std::memory_order_acquire)) {}
    OscHeard h = heard_;
    nameLock_.store(false, std::memory_order_release);
    return h;
}

std::string describeHeard(const OscHeard& h)
{
    std::string out;
    auto part = [&](const char* title) {
        if (!out.empty()) out += "; ";
        out += title;
    };
    bool any = false;
    for (int i = 0; i < OscHeard::kSlots && h.addresses[i][0]; ++i) {
        if (!any) part("OSC addresses no sender format claims: ");
        out += (any ? ", " : "") + std::string(h.addresses[i]) + " (" + std::to_string(h.addressCount[i]) + ")";
        any = true;
    }
    any = false;
    for (int i = 0; i < OscHeard::kSlots && h.junk[i][0]; ++i) {
        if (!any) part("datagrams that are neither OSC nor JSON, starting: ");
        out += (any ? " | " : "") + std::string(h.junk[i]);
        any = true;
    }
    any = false;
    for (int i = 0; i < OscHeard::kSlots && h.senders[i][0]; ++i) {
        if (!any) part("senders heard: ");
        out += (any ? ", " : "") + std::string(h.senders[i]) + " (" + std::to_string(h.senderCount[i]) + " datagrams)";
        any = true;
    }
    return out.empty() ? std::string("nothing at all") : out;
}

std::string lowRateAdvice(OscFormat format, double rate)
{
    constexpr double kGoodFusionHz = 30.0;   // below this the gyroscope integration and the filter's corrections get coarse
    if (!(rate > 0.0) || rate >= kGoodFusionHz) return "";
    char hz[32];
    std::snprintf(hz, sizeof hz, "%.0f Hz", rate);
    std::string s = std::string("the sensor stream arrives at ") + hz + ", too slow for good fusion (30 Hz or more wanted): ";
    switch (format) {
    case OscFormat::ZigSim: return s + "in ZIG SIM set Settings > MESSAGE RATE (PER SEC) to 60";
    case OscFormat::Ngimu: return s + "in the NGIMU GUI raise Settings > Send Rates > Sensors (100 Hz or more)";
    case OscFormat::Sensors2Osc: return s + "in Sensors2OSC choose the fastest sensor speed its settings offer";
    case OscFormat::GyrOsc: return s + "in GyrOSC raise the update rate";
    default: return s + "raise the sender's rate";
    }
}

} // namespace armadillo::osc
