// `armadillo fuse --in IMU.csv --out Q.csv [--features]` (INTERFACES.md): offline SR-UKF fusion,
// one output row per input row, quaternion device → earth (X east, Y up, Z south).
#include "Cli/CommandLine.h"
#include "Cli/Commands.h"
#include "Core/Csv.h"
#include "Core/Pose.h"
#include "Fusion/OrientationFilter.h"
#include <cmath>
#include <iostream>
#include <stdexcept>
#include <vector>

namespace armadillo::cli {

int runFuse(const Arguments& args)
{
    return guarded("fuse", [&] {
        CommandLine cl("fuse", "--in IMU.csv --out Q.csv [--features]",
                       "Fuses gyro, accelerometer and (optional) magnetometer samples with the square-root\n"
                       "UKF of the thesis (docs/FUSION.md). Input: t,gx,gy,gz,ax,ay,az[,mx,my,mz] in s, rad/s,\n"
                       "m/s² and any magnetometer unit; NaN samples are skipped and counted. Output: t,qw,qx,qy,qz,\n"
                       "one row per input row, q mapping device vectors into the earth frame (X east, Y up,\n"
                       "Z south); --features appends elevation,azimuth,roll in degrees.",
                       {{"--in", "IMU.csv", "IMU file to fuse", true},
                        {"--out", "Q.csv", "quaternion file to write (whole or not at all)", true},
                        {"--features", "", "append elevation,azimuth,roll (degrees) to each row", false},
                        {"--no-mag", "", "ignore the magnetometer columns (6-axis fusion)", false},
                        {"--param", "NAME=VALUE", "set one filter parameter (repeatable; tuning and cross-validation runs,\n"
                                                  "scripts/score-broad.sh): a member of OrientationFilter::Params by name,\n"
                                                  "e.g. headingNoise=0.6, field.normTolerance=0.1; booleans 0/1", false}});
        if (!cl.parse(args)) return 0;
        checkOutputPath("--out", cl.value("--out"));   // before the fusion, not after it
        fusion::OrientationFilter::Params params = fusion::OrientationFilter::defaultParams();
        if (cl.has("--no-mag")) params.useMagnetometer = false;
        for (const std::string& setting : cl.values("--param")) {
            const auto eq = setting.find('=');
            const std::string name = setting.substr(0, eq);
            double value = 0.0;
            std::size_t used = 0;
            try {
                if (eq != std::string::npos) value = std::stod(setting.substr(eq + 1), &used);
            } catch (const std::exception&) {
                used = 0;
            }
            if (eq == std::string::npos || used == 0 || used != setting.size() - eq - 1 || !std::isfinite(value))
                throw UsageError("--param " + setting + ": expected NAME=NUMBER");
            if (!fusion::OrientationFilter::setParameter(params, name, value))
                throw UsageError("--param " + setting + ": no filter parameter '" + name + "'");
        }
        const core::CsvTable table = core::CsvTable::read(cl.value("--in"));
        const std::vector<core::ImuSample> samples = readImu(table);
        fusion::OrientationFilter filter(params);
        const bool features = cl.has("--features");
        std::vector<std::string> header {"t", "qw", "qx", "qy", "qz"};
        if (features) header.insert(header.end(), {"elevation", "azimuth", "roll"});
        core::CsvWriter out(header);
        for (std::size_t row = 0; row < samples.size(); ++row) {
            const core::ImuSample& s = samples[row];
            filter.update(s);
            // Before the first usable sample there is no estimate: the rest orientation stands in.
            const Eigen::Quaterniond q = filter.orientation();
            // readImu refuses values no sensor makes; should the filter still lose its way, the
            // row is named instead of writing NaN quaternions.
            if (!q.coeffs().allFinite()) table.fail(row, table.columnIndex("t"), "fusion diverged at this sample (no quaternion written)");
            if (features) {
                const core::Pose p = core::quaternionToPose(q);
                out.row({s.t, q.w(), q.x(), q.y(), q.z(), p.elevationDeg, p.azimuthDeg, p.rollDeg});
            } else {
                out.row({s.t, q.w(), q.x(), q.y(), q.z()});
            }
        }
        out.save(cl.value("--out"));
        std::cerr << "fuse: " << samples.size() << " samples, " << filter.skippedSamples() << " skipped, "
                  << filter.magneticRejections() << " magnetometer samples rejected, " << filter.recovery().gaps
                  << " gaps (" << filter.recovery().bridged << " bridged, " << filter.recovery().reacquired
                  << " re-acquired, longest " << filter.recovery().longestGap << " s), " << filter.recovery().headingResets
                  << " heading and " << filter.recovery().tiltResets << " tilt resets, " << filter.recovery().reacquireSteps
                  << " re-acquisition steps"
                  << (filter.initialised() ? "" : " (no usable sample: rest orientation written)") << "\n";
        return 0;
    });
}

} // namespace armadillo::cli
