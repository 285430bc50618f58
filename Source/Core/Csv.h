#pragma once
// The CSV formats of INTERFACES.md: a header row is required, columns come in any order,
// '#' lines are comments, every value is a number (or NaN). Bad input is refused with an
// InputError naming file, line and column; outputs are written atomically.
#include "Core/Pose.h"
#include "Core/Types.h"
#include <Eigen/Geometry>
#include <string>
#include <string_view>
#include <vector>

namespace armadillo::core {

/// A parsed numeric table. Rows keep the line number they came from, for later messages.
class CsvTable {
public:
    /// Reads and parses a file; throws IoError (cannot read) or InputError (bad content).
    static CsvTable read(const std::string& path);
    /// Parses text; `source` names it in error messages.
    static CsvTable parse(std::string_view text, const std::string& source);

    const std::string& source() const noexcept { return source_; }
    const std::vector<std::string>& header() const noexcept { return header_; }
    bool hasColumn(std::string_view name) const noexcept { return columnIndex(name) >= 0; }
    int columnIndex(std::string_view name) const noexcept;
    /// Index of a column that must exist; throws InputError naming the file otherwise.
    int requireColumn(std::string_view name) const;
    std::size_t rowCount() const noexcept { return lines_.size(); }
    double value(std::size_t row, int column) const noexcept { return values_[row * header_.size() + static_cast<std::size_t>(column)]; }
    long lineOf(std::size_t row) const noexcept { return lines_[row]; }
    long headerLine() const noexcept { return headerLine_; }

    /// Refuses the table unless column `name` is finite and never decreases (time).
    void requireTimeColumn(std::string_view name = "t") const;
    /// Throws an InputError pointing at (row, column).
    [[noreturn]] void fail(std::size_t row, int column, const std::string& message) const;

private:
    std::string source_;
    std::vector<std::string> header_;
    long headerLine_ = 0;
    std::vector<double> values_;
    std::vector<long> lines_;
};

/// Builds CSV text; numbers are written with enough digits to round-trip what matters.
class CsvWriter {
public:
    explicit CsvWriter(const std::vector<std::string>& header);
    CsvWriter& comment(std::string_view text);
    void row(const double* values, std::size_t count, int precision = 9);
    void row(std::initializer_list<double> values, int precision = 9) { row(values.begin(), values.size(), precision); }
    const std::string& text() const noexcept { return text_; }
    void save(const std::string& path) const;   ///< atomic: whole or nothing

private:
    std::size_t columns_;
    std::string text_;
};

/// Appends a number in the shortest form with at most `precision` significant digits; NaN as "nan".
void appendNumber(std::string& out, double value, int precision = 9);
/// Appends one text field, quoted as RFC 4180 when it holds a comma, a quote or a line break
/// (quotes doubled); as it is otherwise.
void appendCsvField(std::string& out, std::string_view field);

// --- The typed formats -------------------------------------------------------------------------

enum class MotionKind { Imu, Quaternion, Pose, Unknown };
/// Tells a motion file apart by its header: IMU (gx..az), quaternion (qw..qz) or pose.
MotionKind detectMotionKind(const CsvTable& table);

/// Largest magnitudes readImu accepts: far beyond any MEMS sensor (±2000 °/s ≈ 35 rad/s, ±400 g),
/// so only typos and garbage are refused. The magnetometer is in any unit (raw counts, µT, nT).
inline constexpr double kMaxImuGyro = 1.0e3;    ///< rad/s
inline constexpr double kMaxImuAccel = 1.0e4;   ///< m/s²
inline constexpr double kMaxImuMag = 1.0e9;
/// t,gx,gy,gz,ax,ay,az[,mx,my,mz]; magnetometer columns optional (absent ⇒ NaN). NaN marks a
/// missing value; infinities and magnitudes beyond the limits above are refused (InputError
/// naming file, line and column).
std::vector<ImuSample> readImu(const CsvTable& table);

struct TimedQuaternion {
    double t = 0.0;
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
};
/// t,qw,qx,qy,qz; every quaternion must be finite and non-zero (it is normalised).
std::vector<TimedQuaternion> readQuaternions(const CsvTable& table);
void writeQuaternions(const std::string& path, const std::vector<TimedQuaternion>& rows);

struct TimedPose {
    double t = 0.0;
    Pose pose {};
};
/// t,elevation,azimuth,roll in degrees.
std::vector<TimedPose> readPoses(const CsvTable& table);
void writePoses(const std::string& path, const std::vector<TimedPose>& rows);

struct TactileRow {
    double t = 0.0;
    MotorLevels levels {};
};
/// t,m1..m9 (and m10..m12 when back motors are on): exact integer levels 0..15.
std::vector<TactileRow> readTactile(const CsvTable& table, int* motorCount = nullptr);
std::string tactileCsvText(const std::vector<TactileRow>& rows, int motorCount);
void writeTactile(const std::string& path, const std::vector<TactileRow>& rows, int motorCount);

/// Any motion file as orientations (IMU files are not accepted here: they need fusion first).
std::vector<TimedQuaternion> motionAsQuaternions(const CsvTable& table);

} // namespace armadillo::core
