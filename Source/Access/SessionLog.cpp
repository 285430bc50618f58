#include "Access/SessionLog.h"
#include "Core/Csv.h"

namespace armadillo::access {

void appendSessionLogRow(std::string& log, double t, const char* event, const PlannedTrial* trial, int number, const std::string& prompt,
                         int unit, int step, braille::MotorSet motors, bool hasMotors, const std::string& answer, int correct)
{
    appendNumber(log, t, 9);
    log += std::string(",") + event + ",";
    if (trial) {
        log += trial->stage + "," + std::to_string(number) + ",";
        appendCsvField(log, trial->expected);
    } else {
        log += ",,";
    }
    log += ",";
    appendCsvField(log, prompt);
    log += ",,,";   // posture, roll: nothing moves in passive drawing
    if (unit >= 0) log += std::to_string(unit + 1) + "," + std::to_string(step + 1);
    else log += ",";
    log += ",";
    if (hasMotors) appendCsvField(log, braille::motorList(motors));
    log += ",";
    appendCsvField(log, answer);
    log += ",";
    if (correct >= 0) log += std::to_string(correct);
    log += "\n";
}

} // namespace armadillo::access
