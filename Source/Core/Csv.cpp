#include "Core/Csv.h"
#include "Core/AtomicFile.h"
#include "Core/Errors.h"
#include "Core/Pose.h"
#include <charconv>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace armadillo::core {
namespace {

std::string_view trim(std::string_view s)
{
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
    return s;
}

bool equalsIgnoreCase(std::string_view a, std::string_view b)
{
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const char x = static_cast<char>(a[i] | 0x20), y = static_cast<char>(b[i] | 0x20);
        if (x != y) return false;
    }
    return true;
}

/// Splits one line at commas into `fields` (views into the line).
void splitFields(std::string_view line, std::vector<std::string_view>& fields)
{
    fields.clear();
    std::size_t start = 0;
    for (;;) {
        const std::size_t comma = line.find(',', start);
        fields.push_back(trim(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
        if (comma == std::string_view::npos) break;
        start = comma + 1;
    }
}

bool parseNumber(std::string_view s, double& out)
{
    if (s.empty()) return false;
    if (equalsIgnoreCase(s, "nan")) {
        out = kNaN;
        return true;
    }
    if (s.front() == '+') s.remove_prefix(1);
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    return ec == std::errc() && end == s.data() + s.size();
}

} // namespace

CsvTable CsvTable::read(const std::string& path)
{
    return parse(readWholeFile(path), path);
}

CsvTable CsvTable::parse(std::string_view text, const std::string& source)
{
    CsvTable t;
    t.source_ = source;
    std::vector<std::string_view> fields;
    long lineNo = 0;
    std::size_t pos = 0;
    if (text.size() >= 3 && std::memcmp(text.data(), "\xEF\xBB\xBF", 3) == 0) pos = 3;   // UTF-8 BOM
    while (pos < text.size()) {
        const std::size_t nl = text.find('\n', pos);
        const std::string_view raw = text.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos);
        pos = nl == std::string_view::npos ? text.size() : nl + 1;
        ++lineNo;
        const std::string_view line = trim(raw);
        if (line.empty() || line.front() == '#') continue;
        if (line.find('\0') != std::string_view::npos)
            throw InputError(source, lineNo, "", "binary data (NUL byte) where CSV text was expected");
        splitFields(line, fields);
        if (t.header_.empty()) {
            t.headerLine_ = lineNo;
            for (std::size_t i = 0; i < fields.size(); ++i) {
                const std::string_view name = fields[i];
                if (name.empty()) throw InputError(source, lineNo, "", "header column " + std::to_string(i + 1) + " has no name");
                double dummy;
                if (parseNumber(name, dummy))
                    throw InputError(source, lineNo, std::string(name), "the first line must be a header row naming the columns, not data");
                for (const auto& seen : t.header_)
                    if (seen == name) throw InputError(source, lineNo, std::string(name), "column named twice in the header");
                t.header_.emplace_back(name);
            }
            continue;
        }
        if (fields.size() != t.header_.size())
            throw InputError(source, lineNo, "", "has " + std::to_string(fields.size()) + " values but the header has "
                                                     + std::to_string(t.header_.size()) + " columns");
        for (std::size_t i = 0; i < fields.size(); ++i) {
            double v;
            if (!parseNumber(fields[i], v))
                throw InputError(source, lineNo, t.header_[i],
                                 fields[i].empty() ? std::string("empty value") : "'" + std::string(fields[i].substr(0, 40)) + "' is not a number");
            t.values_.push_back(v);
        }
        t.lines_.push_back(lineNo);
    }
    if (t.header_.empty()) throw InputError(source, 0, "", "empty file: no header row and no data");
    if (t.lines_.empty()) throw InputError(source, t.headerLine_, "", "no data rows after the header");
    return t;
}

int CsvTable::columnIndex(std::string_view name) const noexcept
{
    for (std::size_t i = 0; i < header_.size(); ++i)
        if (header_[i] == name) return static_cast<int>(i);
    return -1;
}

int CsvTable::requireColumn(std::string_view name) const
{
    const int i = columnIndex(name);
    if (i < 0) {
        std::string have;
        for (const auto& h : header_) have += (have.empty() ? "" : ",") + h;
        throw InputError(source_, headerLine_, std::string(name), "missing column (the header has: " + have + ")");
    }
    return i;
}

void CsvTable::fail(std::size_t row, int column, const std::string& message) const
{
    throw InputError(source_, lineOf(row), column >= 0 ? header_[static_cast<std::size_t>(column)] : std::string(), message);
}

void CsvTable::requireTimeColumn(std::string_view name) const
{
    const int c = requireColumn(name);
    double previous = -INFINITY;
    for (std::size_t r = 0; r < rowCount(); ++r) {
        const double t = value(r, c);
        if (!std::isfinite(t)) fail(r, c, "time must be a finite number");
        if (t < previous) fail(r, c, "time goes backwards (" + std::to_string(t) + " after " + std::to_string(previous) + ")");
        previous = t;
    }
}

// --- Writing -------------------------------------------------------------------------------------

void appendNumber(std::string& out, double value, int precision)
{
    if (std::isnan(value)) {
        out += "nan";
        return;
    }
    char buf[64];
    const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, value, std::chars_format::general, precision);
    out.append(buf, ec == std::errc() ? end : buf);
}

void appendCsvField(std::string& out, std::string_view field)
{
    if (field.find_first_of(",\"\n\r") == std::string_view::npos) {
        out += field;
        return;
    }
    out += '"';
    for (char c : field) {
        if (c == '"') out += '"';
        out += c;
    }
    out += '"';
}

CsvWriter::CsvWriter(const std::vector<std::string>& header) : columns_(header.size())
{
    for (std::size_t i = 0; i < header.size(); ++i) {
        if (i) text_ += ',';
        text_ += header[i];
    }
    text_ += '\n';
}

CsvWriter& CsvWriter::comment(std::string_view text)
{
    text_ += "# ";
    text_ += text;
    text_ += '\n';
    return *this;
}

void CsvWriter::row(const double* values, std::size_t count, int precision)
{
    for (std::size_t i = 0; i < count && i < columns_; ++i) {
        if (i) text_ += ',';
        appendNumber(text_, values[i], precision);
    }
    text_ += '\n';
}

void CsvWriter::save(const std::string& path) const { writeFileAtomically(path, text_); }

// --- Typed formats -------------------------------------------------------------------------------

MotionKind detectMotionKind(const CsvTable& t)
{
    if (t.hasColumn("gx") || t.hasColumn("ax")) return MotionKind::Imu;
    if (t.hasColumn("qw")) return MotionKind::Quaternion;
    if (t.hasColumn("elevation") || t.hasColumn("azimuth") || t.hasColumn("roll")) return MotionKind::Pose;
    return MotionKind::Unknown;
}

std::vector<ImuSample> readImu(const CsvTable& t)
{
    t.requireTimeColumn("t");
    const int ct = t.requireColumn("t");
    int g[3], a[3], m[3];
    const char* gn[3] = {"gx", "gy", "gz"};
    const char* an[3] = {"ax", "ay", "az"};
    const char* mn[3] = {"mx", "my", "mz"};
    for (int i = 0; i < 3; ++i) {
        g[i] = t.requireColumn(gn[i]);
        a[i] = t.requireColumn(an[i]);
        m[i] = t.columnIndex(mn[i]);
    }
    const int magCount = (m[0] >= 0) + (m[1] >= 0) + (m[2] >= 0);
    if (magCount != 0 && magCount != 3)
        for (int i = 0; i < 3; ++i)
            if (m[i] < 0) t.requireColumn(mn[i]);   // names the missing one
    // NaN is a missing value (skipped by fusion); infinity and magnitudes no arm or sensor makes
    // are refused here, naming the cell, rather than turned into NaN orientations later.
    auto check = [&](std::size_t r, int column, double v, double limit, const char* what) {
        if (std::isnan(v)) return;
        if (!std::isfinite(v)) t.fail(r, column, std::string(what) + " must be a finite number (or NaN for a missing value)");
        if (std::abs(v) > limit)
        {
            std::string text;
            appendNumber(text, v, 6);
            std::string most;
            appendNumber(most, limit, 6);
            t.fail(r, column, std::string(what) + " " + text + " is beyond any sensor (|value| at most " + most + ")");
        }
    };
    std::vector<ImuSample> out(t.rowCount());
    for (std::size_t r = 0; r < t.rowCount(); ++r) {
        ImuSample& s = out[r];
        s.t = t.value(r, ct);
        for (int i = 0; i < 3; ++i) {
            s.gyro[i] = t.value(r, g[i]);
            s.accel[i] = t.value(r, a[i]);
            s.mag[i] = magCount ? t.value(r, m[i]) : kNaN;
            check(r, g[i], s.gyro[i], kMaxImuGyro, "angular rate (rad/s)");
            check(r, a[i], s.accel[i], kMaxImuAccel, "acceleration (m/s²)");
            if (magCount) check(r, m[i], s.mag[i], kMaxImuMag, "magnetic field");
        }
    }
    return out;
}

std::vector<TimedQuaternion> readQuaternions(const CsvTable& t)
{
    t.requireTimeColumn("t");
    const int ct = t.requireColumn("t");
    const int c[4] = {t.requireColumn("qw"), t.requireColumn("qx"), t.requireColumn("qy"), t.requireColumn("qz")};
    std::vector<TimedQuaternion> out(t.rowCount());
    for (std::size_t r = 0; r < t.rowCount(); ++r) {
        double v[4];
        for (int i = 0; i < 4; ++i) {
            v[i] = t.value(r, c[i]);
            if (!std::isfinite(v[i])) t.fail(r, c[i], "quaternion component must be a finite number");
        }
        // A rotation's quaternion has length 1; within 10 % it is rounding and is normalised,
        // beyond it the row is refused (Core/Pose.h, isRotationLength).
        if (!isRotationLength(v[0], v[1], v[2], v[3])) {
            // The length for the message, scaled so that 1e200 and 1e-300 are said as they are.
            const double big = std::max({std::abs(v[0]), std::abs(v[1]), std::abs(v[2]), std::abs(v[3])});
            double sum = 0.0;
            for (double x : v) sum += big > 0.0 ? (x / big) * (x / big) : 0.0;
            char what[160];
            std::snprintf(what, sizeof what, "quaternion has length %.3g; a rotation's quaternion has length 1 (within 10%%)",
                          big * std::sqrt(sum));
            t.fail(r, c[0], what);
        }
        const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[3] * v[3]);
        out[r].t = t.value(r, ct);
        out[r].q = Eigen::Quaterniond(v[0] / n, v[1] / n, v[2] / n, v[3] / n);
    }
    return out;
}

void writeQuaternions(const std::string& path, const std::vector<TimedQuaternion>& rows)
{
    CsvWriter w({"t", "qw", "qx", "qy", "qz"});
    for (const auto& r : rows) w.row({r.t, r.q.w(), r.q.x(), r.q.y(), r.q.z()});
    w.save(path);
}

std::vector<TimedPose> readPoses(const CsvTable& t)
{
    t.requireTimeColumn("t");
    const int ct = t.requireColumn("t");
    const int ce = t.requireColumn("elevation"), ca = t.requireColumn("azimuth"), cr = t.requireColumn("roll");
    std::vector<TimedPose> out(t.rowCount());
    for (std::size_t r = 0; r < t.rowCount(); ++r) {
        for (int c : {ce, ca, cr})
            if (!std::isfinite(t.value(r, c))) t.fail(r, c, "angle must be a finite number of degrees");
        if (std::abs(t.value(r, ce)) > 90.0) t.fail(r, ce, "elevation must lie in -90..90 degrees");
        for (int c : {ca, cr})   // any angle is allowed, but a million degrees is a typo, not a turn
            if (std::abs(t.value(r, c)) > 1.0e6) t.fail(r, c, "angle beyond ±1e6 degrees");
        out[r].t = t.value(r, ct);
        out[r].pose = Pose {t.value(r, ce), t.value(r, ca), t.value(r, cr)};
    }
    return out;
}

void writePoses(const std::string& path, const std::vector<TimedPose>& rows)
{
    CsvWriter w({"t", "elevation", "azimuth", "roll"});
    for (const auto& r : rows) w.row({r.t, r.pose.elevationDeg, r.pose.azimuthDeg, r.pose.rollDeg});
    w.save(path);
}

std::vector<TactileRow> readTactile(const CsvTable& t, int* motorCount)
{
    t.requireTimeColumn("t");
    const int ct = t.requireColumn("t");
    int cols[kMaxMotors];
    int count = 0;
    for (int k = 1; k <= kMaxMotors; ++k) {
        const int c = t.columnIndex("m" + std::to_string(k));
        if (c < 0) break;
        cols[count++] = c;
    }
    if (count < kGridMotors) t.requireColumn("m" + std::to_string(count + 1));
    std::vector<TactileRow> out(t.rowCount());
    for (std::size_t r = 0; r < t.rowCount(); ++r) {
        out[r].t = t.value(r, ct);
        for (int k = 0; k < count; ++k) {
            const double v = t.value(r, cols[k]);
            if (!(v >= 0.0 && v <= kMaxLevel) || v != std::floor(v))
                t.fail(r, cols[k], "motor level must be a whole number 0..15");
            out[r].levels[static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(v);
        }
    }
    if (motorCount) *motorCount = count;
    return out;
}

std::string tactileCsvText(const std::vector<TactileRow>& rows, int motorCount)
{
    std::string s = "t";
    for (int k = 1; k <= motorCount; ++k) s += ",m" + std::to_string(k);
    s += '\n';
    for (const auto& r : rows) {
        appendNumber(s, r.t, 9);
        for (int k = 0; k < motorCount; ++k) {
            s += ',';
            s += std::to_string(r.levels[static_cast<std::size_t>(k)]);
        }
        s += '\n';
    }
    return s;
}

void writeTactile(const std::string& path, const std::vector<TactileRow>& rows, int motorCount)
{
    writeFileAtomically(path, tactileCsvText(rows, motorCount));
}

std::vector<TimedQuaternion> motionAsQuaternions(const CsvTable& t)
{
    switch (detectMotionKind(t)) {
    case MotionKind::Quaternion: return readQuaternions(t);
    case MotionKind::Pose: {
        std::vector<TimedQuaternion> out;
        for (const auto& p : readPoses(t)) out.push_back({p.t, poseToQuaternion(p.pose)});
        return out;
    }
    case MotionKind::Imu:
        throw InputError(t.source(), t.headerLine(), "", "an IMU file needs fusion: use it where IMU input is accepted");
    case MotionKind::Unknown: break;
    }
    throw InputError(t.source(), t.headerLine(), "",
                     "not a motion file: the header needs t with gx,gy,gz,ax,ay,az (IMU), qw,qx,qy,qz (quaternion) or elevation,azimuth,roll (pose)");
}

} // namespace armadillo::core
