#include "Access/SessionLog.h"
#include "Core/Csv.h"

namespace armadillo::access {

namespace {
void field(std::string& log, const std::string& f)
{
    if (f.find_first_of(",\"\n\r") == std::string::npos) {
        log += f;
        return;
    }
    log += '"';
    for (char c : f) {
        if (c == '"') log += '"';
        log += c;
    }
    log += '"';
}
} // namespace

void appendSessionLogRow(std::string& log, double t, const char* event, const PlannedTrial* trial, int number, const std::string& prompt,
                         int unit, int step, braille::MotorSet motors, bool hasMotors, const std::string& answer, int correct)
{
    appendNumber(log, t, 9);
    log += std::string(",") + event + ",";
    if (trial) {
        log += trial->stage + "," + std::to_string(number) + ",";
        field(log, trial->expected);
    } else {
        log += ",,";
    }
    log += ",";
    field(log, prompt);
    log += ",,,";   // posture, roll: nothing moves in passive drawing
    if (unit >= 0) log += std::to_string(unit + 1) + "," + std::to_string(step + 1);
    else log += ",";
    log += ",";
    if (hasMotors) field(log, braille::motorList(motors));
    log += ",";
    field(log, answer);
    log += ",";
    if (correct >= 0) log += std::to_string(correct);
    log += "\n";
}

} // namespace armadillo::access
