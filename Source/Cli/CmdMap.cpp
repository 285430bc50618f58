#include "Cli/CommandLine.h"
#include "Cli/Commands.h"
#include "Core/AtomicFile.h"
#include "Core/Csv.h"
#include "Core/Errors.h"
#include "Fusion/ArmTracker.h"
#include "Mapping/Mapper.h"
#include "Mapping/MappingSpec.h"
#include "Mapping/Posture.h"
#include <iostream>

namespace armadillo::cli {

namespace {

int check(const std::vector<std::string>& rest)
{
    if (rest.size() != 1) throw UsageError("map check needs one PRESET|FILE");
    const mapping::MappingDocument doc = mapping::loadMapping(rest[0]);
    const auto set = mapping::MappingSet::build(doc, {{}, rest[0]});
    // Mappings that need a second arm (a left-arm or arms.* source): with one arm they send nothing.
    std::size_t twoArms = 0;
    for (const mapping::MappingSpec& m : doc.mappings)
        twoArms += m.source.arm == 1 || mapping::isTwoArmSource(m.source.kind);
    std::size_t stage = 0;   // mappings that step the set list or panic (docs/STAGE.md)
    for (const mapping::MappingSpec& m : doc.mappings) stage += m.to.kind == mapping::DestinationKind::Stage;
    std::cout << "{\"mappings\":" << doc.mappings.size() << ",\"postures\":" << doc.postures.size()
              << ",\"osc_targets\":" << set->oscTargets().size() << ",\"scene_parameters\":" << set->sceneParamIds().size()
              << ",\"two_arm_mappings\":" << twoArms << ",\"stage_mappings\":" << stage << "}\n";
    return 0;
}

int show(const std::vector<std::string>& rest)
{
    if (rest.size() != 1) throw UsageError("map show needs one PRESET|FILE");
    std::cout << mapping::toJson(mapping::loadMapping(rest[0]));
    return 0;
}

/// A posture from a motion file of the performer holding it (IMU files are fused first).
int learnPosture(const CommandLine& cl)
{
    const std::string name = cl.value("--name");
    if (name.empty()) throw UsageError("learn-posture needs --name NAME");
    if (!cl.has("--motion")) throw UsageError("learn-posture needs --motion FILE (the performer holding the pose)");
    if (!cl.has("--out")) throw UsageError("learn-posture needs --out OUT.json");
    const double from = cl.number("--from", -1e300), to = cl.number("--to", 1e300);
    if (!(to > from)) throw UsageError("--to must come after --from");

    mapping::MappingDocument doc;
    if (cl.has("--map")) doc = mapping::loadMapping(cl.value("--map"));
    const core::CsvTable table = core::CsvTable::read(cl.value("--motion"));
    fusion::ArmTracker tracker;
    mapping::PostureRecorder recorder;
    const auto take = [&](double t, const core::ArmState& arm) {
        if (arm.valid && t >= from && t <= to) recorder.add(arm.q, arm.gyro.allFinite() ? core::radToDeg(arm.gyro.norm()) : 0.0);
    };
    if (detectMotionKind(table) == core::MotionKind::Imu) {
        for (const core::ImuSample& s : readImu(table)) take(s.t, tracker.update(s));
    } else {
        for (const core::TimedQuaternion& q : motionAsQuaternions(table)) take(q.t, tracker.updateOrientation(q.t, q.q));
    }
    mapping::PostureSpec posture;
    try {
        posture = recorder.finish(name);
    } catch (const core::InputError& e) {
        throw core::InputError(cl.value("--motion"), 0, "", e.what());
    }
    bool replaced = false;
    for (auto& p : doc.postures) {
        if (p.name == name) {
            p = posture;
            replaced = true;
        }
    }
    if (!replaced) {
        if (doc.postures.size() >= static_cast<std::size_t>(mapping::kMaxPostures)) throw core::InputError(cl.value("--map"), 0, "", "already 16 postures");
        doc.postures.push_back(posture);
    }
    const std::string text = mapping::toJson(doc);
    mapping::parseMappingDocument(text, cl.value("--out"));   // what is written reads back
    core::writeFileAtomically(cl.value("--out"), text);
    std::cout << "{\"posture\":\"" << name << "\",\"examples\":" << posture.examples.size() << ",\"radius_deg\":" << posture.radiusDeg
              << ",\"samples\":" << recorder.count() << "}\n";
    return 0;
}

} // namespace

int runMap(const Arguments& args)
{
    return guarded("map", [&] {
        CommandLine cl("map", "check PRESET|FILE | show PRESET|FILE | learn-posture --name NAME --motion FILE --out OUT.json [options]",
                       "Mapping files (docs/MAPPING.md). `check` reads and builds a mapping and prints what it holds (exit 3\n"
                       "with file, line and column for a bad one); `show` prints a preset or file as JSON (a start for\n"
                       "your own: armadillo map show classic > mine.json); `learn-posture` records a posture from a motion\n"
                       "file of the performer holding it (IMU files are fused first; samples faster than 90 deg/s are\n"
                       "left out) and writes it into a mapping file, where `posture:NAME` sources can use it.",
                       {{"--name", "NAME", "learn-posture: the posture's name"},
                        {"--motion", "FILE", "learn-posture: IMU, quaternion or pose CSV of the held pose"},
                        {"--from", "S", "learn-posture: use rows from this time on (s, the file's clock)"},
                        {"--to", "S", "learn-posture: use rows up to this time"},
                        {"--map", "PRESET|FILE", "learn-posture: add to this mapping (default: an empty one); a posture of the same name is replaced"},
                        {"--out", "OUT.json", "learn-posture: the mapping file to write (whole or not at all)"}});
        // The action word comes first; the options after it.
        if (args.empty() || args[0] == "--help" || args[0] == "-h") {
            cl.parse({"--help"});
            return args.empty() ? int(core::kExitUsage) : 0;
        }
        const std::string action = args[0];
        const Arguments rest(args.begin() + 1, args.end());
        if (action == "check") return check(rest);
        if (action == "show") return show(rest);
        if (action == "learn-posture") {
            if (!cl.parse(rest)) return 0;
            return learnPosture(cl);
        }
        throw UsageError("unknown action '" + action + "' (check, show, learn-posture)");
    });
}

} // namespace armadillo::cli
