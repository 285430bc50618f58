// `armadillo calibrate`: the device calibration of thesis §2.4 on stdin/stderr, the same seven
// steps as the app's Calibration window — both present procedures::DeviceCalibration
// (Procedures/DeviceCalibration.h). Each step is one prompt line starting with "? " on stderr (its
// title and instruction); the user answers on stdin: Enter = the step is done (taken as soon as it
// has enough data; until then the program says how far it is and waits), s = skip it (it keeps the
// starting calibration's numbers), q = cancel (nothing written). With --simulate the built-in
// simulated forearm rehearses what each step asks (procedures::CalibrationRehearsal) and Enter takes
// the step once the simulated arm has gone through its movement, so the whole walk can be tried,
// and tested, without a board.
#include "Cli/CommandLine.h"
#include "Cli/LiveOptions.h"
#include "Cli/Commands.h"
#include "Cli/ReaderIo.h"
#include "Core/Errors.h"
#include "Link/Calibration.h"
#include "Live/Sources/GuidedDevice.h"
#include "Procedures/DeviceCalibration.h"
#include <algorithm>
#include <cctype>
#include <iostream>
#include <memory>

namespace armadillo::cli {

int runCalibrate(const Arguments& args)
{
    return guarded("calibrate", [&]() -> int {
        CommandLine cl(
            "calibrate", "(--port NAME | --simulate) --out CAL.json [options]",
            "The device calibration of thesis §2.4, step by step (the app's Calibration window on the\n"
            "command line): gyroscope bias (keep still), accelerometer (each axis down and up), the\n"
            "magnetometer (a level circle, then vertical circles), and the gyroscope scale (one full turn\n"
            "about x, y and z). Each step is one line starting with '? ' on stderr; answer on stdin:\n"
            "Enter when the step is done (it is taken as soon as it has enough data), s to skip it (it\n"
            "keeps the starting calibration's numbers), q to cancel (nothing is written). Writes the\n"
            "calibration file (docs/INTERFACES.md) that play --calibration takes, and prints one JSON line:\n"
            "{\"steps\":7,\"measured\":…,\"skipped\":…,\"packets\":…,\"dropped\":…}.",
            [] {
                std::vector<OptionSpec> o {
                    {"--simulate", "", "the built-in simulated forearm, which does what each step asks (a rehearsal)"},
                    {"--out", "CAL.json", "where the calibration goes (atomic)", true},
                    {"--calibration", "CAL.json", "the starting calibration: what 'still' means, and what a skipped step keeps\n"
                                                  "(default: the built-in one, which matches the simulator)"},
                };
                const auto io = readerIoOptionSpecs();
                const auto device = pickOptions(sourceOptionSpecs(), {"--port", "--baud"});   // the source group (Cli/LiveOptions.h)
                o.insert(o.end(), device.begin(), device.end());
                o.insert(o.end(), io.begin(), io.end());
                return o;
            }());
        if (!cl.parse(args)) return core::kExitOk;
        const DeviceChoice choice = readDeviceOptions(cl);   // the source group (Cli/LiveOptions.h)
        const std::string out = cl.value("--out");
        if (out.empty()) throw UsageError("--out needs a file");
        const int baud = choice.baud;
        ReaderIo io(cl);
        const link::Calibration start = cl.has("--calibration") ? link::loadCalibration(cl.value("--calibration")) : link::defaultCalibration();

        using Step = procedures::DeviceCalibration::Step;
        procedures::DeviceCalibration calibration;
        std::shared_ptr<procedures::CalibrationRehearsal> rehearsal;
        if (cl.has("--simulate")) rehearsal = std::make_shared<procedures::CalibrationRehearsal>();
        // No stimuli: the player only keeps the motors off and counts the link's clock.
        access::TactilePlayer player(tactile::TactileConfig {}, 0.0);
        installInterruptHandlers();
        auto offer = [&calibration](const link::SensorCounts& counts, double t) { calibration.offer(t, counts); };   // link thread: lock-free
        live::GuidedDevice device(choice.port, baud, choice.simulate, false, player, offer, rehearsal);
        device.setInterruptCheck(interrupted);

        calibration.begin(start);
        io.status("device calibration (thesis §2.4): " + std::to_string(procedures::DeviceCalibration::kStepCount) +
                  " steps. Enter when a step is done, s skips it, q cancels");
        // While an answer is awaited: the packets go into the procedure, a silent device ends the
        // wait (exit 4), and a step waited for ("Enter" before it had enough data) ends itself.
        bool waiting = false;
        // With --simulate the simulated arm is the user's: its movement through is the "done".
        auto takeable = [&] { return calibration.ready() && (!rehearsal || rehearsal->performed()); };
        const std::string kReady = "\x01";
        io.setExtraInput([&]() -> std::string {
            device.checkAlive();
            calibration.drain();
            return waiting && takeable() ? kReady : std::string();
        });
        bool cancelled = false;
        while (calibration.running() && !cancelled) {
            if (rehearsal) rehearsal->setStep(calibration.step());
            io.prompt(calibration.stepTitle() + ": " + calibration.instruction() + " (Enter = done, s = skip, q = cancel)",
                      calibration.stepTitle());
            waiting = false;
            for (;;) {
                std::string a = io.readLine();   // AnswersEnded (exit 3, nothing written) when stdin ends
                std::transform(a.begin(), a.end(), a.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
                if (a == "q") {
                    cancelled = true;
                    break;
                }
                if (a == "s") {
                    const Step was = calibration.step();
                    calibration.skip();
                    io.note(std::string(procedures::DeviceCalibration::shortLabel(was)) + " skipped: it keeps the starting numbers");
                    break;
                }
                if (a.empty() || a == kReady) {
                    calibration.drain();
                    const Step was = calibration.step();
                    std::string why;
                    if (rehearsal && !rehearsal->performed()) why = "The simulated arm is still moving through this step.";
                    else if (calibration.next(why)) {
                        io.note(std::string(procedures::DeviceCalibration::shortLabel(was)) + " measured");
                        break;
                    }
                    if (!waiting) io.note(why + " The step ends by itself when it has enough (s skips, q cancels).");
                    waiting = true;
                    continue;
                }
                io.note("Enter = the step is done, s = skip it, q = cancel");
            }
        }
        if (cancelled) {
            calibration.cancel();
            io.status("calibration cancelled: nothing written");
            std::cout << "{\"cancelled\":true}\n";
            return core::kExitOk;
        }
        calibration.save(out);
        const std::string measured = calibration.measuredList(true), kept = calibration.measuredList(false);
        io.status("calibration written to " + out + ": measured " + (measured.empty() ? "nothing" : measured) +
                  (kept.empty() ? "" : "; kept from the start: " + kept));
        int measuredSteps = 0;
        for (int k = 0; k < procedures::DeviceCalibration::kStepCount; ++k) measuredSteps += calibration.measured(static_cast<Step>(k));
        std::cout << "{\"steps\":" << procedures::DeviceCalibration::kStepCount << ",\"measured\":" << measuredSteps
                  << ",\"skipped\":" << procedures::DeviceCalibration::kStepCount - measuredSteps << ",\"packets\":" << calibration.packetsFed()
                  << ",\"dropped\":" << calibration.packetsDropped() << "}\n";
        return core::kExitOk;
    });
}

} // namespace armadillo::cli
