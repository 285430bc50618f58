#include "Access/SessionLog.h"
#include "Core/Csv.h"

namespace armadillo::access {

void appendSessionLogRow(std::string& log, double t, const char* event, const PlannedTrial* trial, int number, const std::string& prompt,
                         int unit, int step, braille::MotorSet motors, bool hasMotors, const std::string& answer, int correct)
{
    core::appendNumber(log, t, 9);
    log += std::string(",") + event + ",";
    if (trial) {
        log += trial->stage + "," + std::to_string(number) + ",";
        core::appendCsvField(log, trial->expected);
    } else {
        log += ",,";
    }
    log += ",";
    core::appendCsvField(log, prompt);
    log += ",,,";   // posture, roll: nothing moves in passive drawing
    if (unit >= 0) log += std::to_string(unit + 1) + "," + std::to_string(step + 1);
    else log += ",";
    log += ",";
    if (hasMotors) core::appendCsvField(log, braille::motorList(motors));
    log += ",";
    core::appendCsvField(log, answer);
    log += ",";
    if (correct >= 0) log += std::to_string(correct);
    log += "\n";
}

} // namespace armadillo::access
