// `armadillo navigate`: walk a route guided by the arm alone (issue 34, docs/NAVIGATION.md).
// The front end only asks and presents: the live session builds the arm's source and motors (a
// device, the simulated forearm or a phone), the walk's position source and the navigation scene
// (Live/Session/LiveSession.h, LiveConfig::walk); this file reads the options, announces the walk and
// keeps its logs. --simulate-walk runs the whole walk offline (Navigation/WalkRehearsal.h).
#include "Cli/CommandLine.h"
#include "Cli/LiveOptions.h"
#include "Cli/Commands.h"
#include "Cli/ReaderIo.h"
#include "Cli/TactorOptions.h"
#include "Cli/SceneOptions.h"
#include "Core/AtomicFile.h"
#include "Core/Errors.h"
#include "Link/Calibration.h"
#include "Link/Mount.h"
#include "Osc/HostPort.h"
#include "Live/Session/LiveSession.h"
#include "Navigation/NavigationRig.h"
#include "Navigation/WalkRehearsal.h"
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <thread>

namespace armadillo::cli {

namespace {

std::string logHeader()
{
    return "t,lat,lon,fix,waypoint,distance_m,bearing_deg,heading_deg,arm_heading_deg,offset_deg,leg_distance_m,off_route,arrived,sensation,mag_disturbed\n";
}

void appendNumber(std::string& out, double v, const char* format)
{
    if (!std::isfinite(v)) {
        out += ',';
        return;
    }
    char buf[40];
    std::snprintf(buf, sizeof buf, format, v);
    out += ',';
    out += buf;
}

void appendRow(std::string& out, const navigation::NavigationLogRecord& r)
{
    char t[32];
    std::snprintf(t, sizeof t, "%.3f", r.t);
    out += t;
    appendNumber(out, r.lat, "%.7f");
    appendNumber(out, r.lon, "%.7f");
    out += ',';
    out += navigation::fixStateName(r.fix);
    out += ',' + std::to_string(r.waypoint);
    appendNumber(out, r.distanceM, "%.2f");
    appendNumber(out, r.bearingDeg, "%.2f");
    appendNumber(out, r.headingDeg, "%.2f");
    appendNumber(out, r.armHeadingDeg, "%.2f");
    appendNumber(out, r.offsetDeg, "%.2f");
    appendNumber(out, r.legDistanceM, "%.2f");
    out += r.offRoute ? ",1" : ",0";
    out += ',' + std::to_string(r.arrivedAt);
    out += ',';
    out += navigation::sensationName(r.sensation);
    out += r.magDisturbed ? ",1\n" : ",0\n";
}

/// What happened since the last call, said once on stderr: arrivals, fix lost/back, off route, the end.
/// With --speak (or a braille display) the same events are also spoken / shown (ReaderIo), for
/// those who want speech; the arm says everything without it.
class Announcer {
public:
    Announcer(const navigation::Route& route, ReaderIo* voice) : route_(route), voice_(voice) {}
    void note(const navigation::NavigationLogRecord& r)
    {
        if (r.arrivedAt > 0) {
            const std::string& name = route_.points[static_cast<std::size_t>(r.arrivedAt - 1)].name;
            std::cerr << "armadillo navigate: arrived at waypoint " << r.arrivedAt << (name.empty() ? "" : " '" + name + "'") << " (t = " << r.t << " s)\n";
            const bool last = r.arrivedAt == static_cast<int>(route_.points.size());
            say("arrived" + (name.empty() ? std::string() : ": " + name) + (last ? ". End of the route." : ""));
            ++arrivals_;
        }
        if (r.fix != fix_) {
            if (r.fix == navigation::FixState::Lost) {
                std::cerr << "armadillo navigate: position fix lost (t = " << r.t << " s): no direction is shown until it is back\n";
                say("position lost");
            } else if (r.fix == navigation::FixState::Ok && fix_ == navigation::FixState::Lost) {
                std::cerr << "armadillo navigate: position fix back (t = " << r.t << " s)\n";
                say("position back");
            }
            fix_ = r.fix;
        }
        if (r.offRoute != offRoute_) {
            std::cerr << "armadillo navigate: " << (r.offRoute ? "off route" : "back on route") << " (t = " << r.t << " s)\n";
            say(r.offRoute ? "off route" : "back on route");
            offRoute_ = r.offRoute;
        }
    }
    int arrivals() const { return arrivals_; }

private:
    void say(const std::string& text)
    {
        if (voice_) voice_->status(text);
    }
    const navigation::Route& route_;
    ReaderIo* voice_ = nullptr;
    navigation::FixState fix_ = navigation::FixState::Waiting;
    bool offRoute_ = false;
    int arrivals_ = 0;
};

std::string tactileRow(double t, const core::MotorLevels& levels)
{
    char buf[96];
    std::snprintf(buf, sizeof buf, "%.4f,%d,%d,%d,%d,%d,%d,%d,%d,%d\n", t, levels[0], levels[1], levels[2], levels[3], levels[4], levels[5], levels[6],
                  levels[7], levels[8]);
    return buf;
}

} // namespace

namespace {

std::vector<OptionSpec> navigateOptionSpecs()
{
    std::vector<OptionSpec> o {
        {"--route", "FILE", "the route: GPX 1.1 (<rte>, <trk> or <wpt>) or a JSON waypoint list", true},
        {"--gpsd", "HOST[:PORT]", "positions from gpsd (port 2947 unless given; 'localhost' for the local one)"},
        {"--osc-in", "PORT", "positions over OSC/UDP on PORT: /armadillo/position lat lon [accuracy_m], ZIG SIM's gps;\n"
                             "without --port/--simulate the arm's motion comes from the same port (a phone: ZIG SIM motion + gps)"},
        {"--mount", "NAME", "with --osc-in as the arm: how the phone is worn (docs/SENSORS.md; as `play --mount`)"},
        {"--simulate-walk", "", "a simulated walker follows the motors (with --simulate; offline, deterministic)"},
        {"--simulate", "", "the built-in simulated forearm (with --gpsd: it holds still; with --simulate-walk: the walker's arm)"},
        {"--motion", "FILE", "with --simulate and --gpsd: the simulated forearm moves as this pose/quaternion CSV"},
        {"--profile", "PROFILE.json", "the reader's touch profile (as `play`)"},
        {"--arm", "right|left", "the arm wearing the device (default right)"},
        {"--log", "NAV.csv", "one row per control update: t,lat,lon,fix,waypoint,distance_m,bearing_deg,heading_deg,…"},
        {"--tactile", "T.csv", "every motor packet: t,m1..m9"},
        {"--session-log", "SESSION.csv", "a live walk's session log, as `play --log`: one row per sensor packet (t, raw counts,\n"
                                         "calibrated SI values, qw,qx,qy,qz, the link's counters)"},
        {"--osc-out", "HOST:PORT", "a live walk's arm as OSC, as `play --osc-out`: orientation, pose, gyro, motors, gestures"},
        {"--seconds", "N", "stop after N seconds (simulated seconds with --simulate-walk)"},
        {"--arrival-radius", "M", "arrived within M metres of a waypoint (default 8)"},
        {"--off-route", "M", "off route further than M metres from the leg (default 20)"},
        {"--names", "shorthand|full|none", "how waypoint names are spelt on the arm (default shorthand: a sign word's §5.3 shorthand)"},
        {"--heading-offset", "DEG", "a known strap offset (thumb − walking direction), used until one is learned"},
        {"--no-learn", "", "do not learn the heading offset from the walk (§5.3); --heading-offset only"},
        {"--level", "L", "level of the sensations, 1..15 (default 5; the safety stage still decides)"},
        {"--strap-offset", "DEG", "with --simulate-walk: the simulated strap's offset (default 20)"},
        {"--seed", "N", "with --simulate-walk: the walker's and its GPS's random seed (default 1)"},
    };
    // The device: as play's source group says it (Cli/LiveOptions.h).
    const auto device = pickOptions(sourceOptionSpecs(), {"--port", "--baud", "--calibration"});
    o.insert(o.begin() + 4, device.begin(), device.end());
    const auto io = readerIoOptionSpecs();   // --speak, --speech, --rate, --brlapi, --braille-display
    o.insert(o.end(), io.begin(), io.end());
    // The motors on a tactor rig (docs/TACTORS.md), beside the device or the simulator.
    const auto tactorOptions = tactorOptionSpecs(true);
    o.insert(o.end(), tactorOptions.begin(), tactorOptions.end());
    const auto web = webOptionSpecs();   // the walk as a web page (as play's)
    o.insert(o.end(), web.begin(), web.end());
    return o;
}

/// What `navigate` was asked for, every option checked and the route read (exit 2, 3 or 4 before
/// anything runs).
struct NavigateRequest {
    bool gpsd = false, walk = false, osc = false, armFromOsc = false;
    int oscPort = 0;
    navigation::NavigationOptions options;
    double seconds = -1.0;
    std::string arm, logPath, tactilePath;
    std::string sessionLogPath, oscOut;   ///< a live walk's: play's --log and --osc-out
    std::shared_ptr<const navigation::Route> route;
};

/// The choice of sources: one position source, one arm, and the options that go with each.
void checkNavigateSources(const CommandLine& cl, NavigateRequest& r)
{
    r.gpsd = cl.has("--gpsd");
    r.walk = cl.has("--simulate-walk");
    r.osc = cl.has("--osc-in");
    if (int(r.gpsd) + int(r.walk) + int(r.osc) != 1) throw UsageError("choose one position source: --gpsd HOST[:PORT], --osc-in PORT or --simulate-walk");
    r.oscPort = r.osc ? static_cast<int>(cl.integer("--osc-in", 0, 1, 65535)) : 0;
    r.armFromOsc = r.osc && !cl.has("--port") && !cl.has("--simulate");   // a phone sends motion and positions
    if (int(cl.has("--port")) + int(cl.has("--simulate")) != 1 && !r.armFromOsc)
        throw UsageError("choose the arm: --port NAME or --simulate (or, with --osc-in, the phone's own motion on that port)");
    if (cl.has("--mount") && !r.armFromOsc) throw UsageError("--mount says how a phone is worn: with --osc-in as the arm (no --port, no --simulate)");
    if (r.walk && !cl.has("--simulate")) throw UsageError("--simulate-walk moves the simulated forearm: use it with --simulate");
    if (r.walk && (cl.has("--tactors") || anyTactorSetting(cl))) throw UsageError("--simulate-walk runs offline: the tactor options are for a live walk");
    if (anyTactorSetting(cl) && !cl.has("--tactors")) throw UsageError("the --tactor-* options shape --tactors: give it too");
    if (cl.has("--motion") && (!cl.has("--simulate") || r.walk)) throw UsageError("--motion drives the simulated forearm with --gpsd or --osc-in: use it with --simulate");
    for (const char* o : {"--strap-offset", "--seed"})
        if (cl.has(o) && !r.walk) throw UsageError(std::string(o) + " applies to --simulate-walk");
    if (cl.has("--baud") && !cl.has("--port")) throw UsageError("--baud applies to --port");
    for (const char* o : {"--session-log", "--osc-out"})
        if (cl.has(o) && r.walk) throw UsageError(std::string(o) + " is a live walk's (the arm's packets): --simulate-walk runs offline");
}

/// The guidance's settings.
navigation::NavigationOptions readGuidanceOptions(const CommandLine& cl)
{
    navigation::NavigationOptions options;
    options.guidance.arrivalRadiusM = cl.number("--arrival-radius", 8.0);
    if (!(options.guidance.arrivalRadiusM >= 1.0 && options.guidance.arrivalRadiusM <= 200.0)) throw UsageError("--arrival-radius must be 1…200 m");
    options.guidance.offRouteM = cl.number("--off-route", 20.0);
    if (!(options.guidance.offRouteM >= 5.0 && options.guidance.offRouteM <= 1000.0)) throw UsageError("--off-route must be 5…1000 m");
    options.guidance.backOnRouteM = 0.75 * options.guidance.offRouteM;
    const std::string names = cl.value("--names", "shorthand");
    if (names == "shorthand") options.names = navigation::NameDisplay::Shorthand;
    else if (names == "full") options.names = navigation::NameDisplay::Full;
    else if (names == "none") options.names = navigation::NameDisplay::None;
    else throw UsageError("--names must be shorthand, full or none");
    options.headingOffsetDeg = cl.number("--heading-offset", 0.0);
    if (!(std::fabs(options.headingOffsetDeg) <= 180.0)) throw UsageError("--heading-offset must be −180…180 degrees");
    options.learnHeading = !cl.has("--no-learn");
    options.level = static_cast<float>(cl.number("--level", 5.0));
    if (!(options.level >= 1.0f && options.level <= 15.0f)) throw UsageError("--level must be 1…15");
    return options;
}

NavigateRequest readNavigateRequest(const CommandLine& cl)
{
    NavigateRequest r;
    checkNavigateSources(cl, r);
    r.options = readGuidanceOptions(cl);
    r.seconds = cl.number("--seconds", -1.0);
    if (cl.has("--seconds") && !(r.seconds > 0.0 && r.seconds <= 7 * 24 * 3600.0)) throw UsageError("--seconds must be a positive number of seconds (at most a week)");
    r.arm = cl.value("--arm", "right");
    if (r.arm != "right" && r.arm != "left") throw UsageError("--arm must be right or left");
    r.logPath = cl.value("--log");
    r.tactilePath = cl.value("--tactile");
    if (!r.logPath.empty()) checkOutputPath("--log", r.logPath);
    if (!r.tactilePath.empty()) checkOutputPath("--tactile", r.tactilePath);
    r.sessionLogPath = cl.value("--session-log");
    if (cl.has("--session-log")) checkOutputPath("--session-log", r.sessionLogPath);
    checkDistinctOutputs({{"--log", r.logPath}, {"--tactile", r.tactilePath}, {"--session-log", r.sessionLogPath}});
    if (cl.has("--osc-out")) {
        r.oscOut = cl.value("--osc-out");
        try {
            osc::parseHostPort(r.oscOut);
        } catch (const std::invalid_argument& e) {
            throw UsageError(std::string("--osc-out: ") + e.what());
        }
    }
    if (r.gpsd) navigation::parseGpsdEndpoint(cl.value("--gpsd"));   // InputError (exit 3) for a bad port, before the route is read

    // Inputs: a route that cannot be read is exit 4, one that is not a route 3.
    r.route = std::make_shared<const navigation::Route>(navigation::readRouteFile(cl.value("--route")));
    const navigation::Route& route = *r.route;
    std::cerr << "armadillo navigate: route '" << (route.name.empty() ? route.source : route.name) << "': start and " << route.points.size() - 1
              << " waypoints, " << static_cast<long>(std::lround(route.lengthM())) << " m\n";
    return r;
}

/// The navigation log as the walk goes: each record announced (stderr, and speech or a braille
/// display when asked) and, with --log, kept as a row. A live walk's log grows under its own
/// name as the walk goes (a crash keeps it; an existing file is kept aside: docs/SECURITY.md);
/// the offline walk's is written whole at its end.
class WalkLog {
public:
    WalkLog(const navigation::Route& route, ReaderIo* voice, const std::string& path, bool growing) : announcer_(route, voice), path_(path)
    {
        if (!path_.empty() && growing) file_ = std::make_unique<core::RecordingFile>(path_);   // IoError naming the path
    }
    /// "NAV.csv existed: kept as NAV.csv.1" when it did, else "".
    std::string keptAside() const { return file_ && !file_->keptAs().empty() ? core::keptAsideNote(path_, file_->keptAs()) : std::string(); }
    void drain(navigation::NavigationLink& link)
    {
        navigation::NavigationLogRecord r;
        while (link.log.pop(r)) {
            announcer_.note(r);
            if (!path_.empty()) appendRow(text_, r);
        }
        if (file_ && !text_.empty()) {   // whole rows, memory bounded however long the walk
            file_->append(text_);
            text_.clear();
        }
    }
    void write()
    {
        if (path_.empty()) return;
        if (!file_) {
            core::writeFileAtomically(path_, text_);
            return;
        }
        file_->append(text_);
        text_.clear();
        file_->finish();
    }

private:
    Announcer announcer_;
    std::string path_;
    std::unique_ptr<core::RecordingFile> file_;
    std::string text_ = logHeader();
};

/// --simulate-walk: the whole walk offline; the walker feels the motors, its GPS feeds the scene.
int runSimulatedWalk(const CommandLine& cl, const NavigateRequest& req)
{
    navigation::WalkerParams w;
    w.strapOffsetDeg = cl.number("--strap-offset", 20.0);
    if (!(std::fabs(w.strapOffsetDeg) <= 180.0)) throw UsageError("--strap-offset must be −180…180 degrees");
    w.seed = static_cast<std::uint64_t>(cl.integer("--seed", 1, 0, 1L << 62));
    if (cl.has("--speak") || cl.has("--speech") || cl.has("--brlapi") || cl.has("--braille-display"))
        throw UsageError("--speak and the braille display are for a live walk, not --simulate-walk");
    if (cl.has("--rate")) throw UsageError("--rate sets the speech rate: use it with --speak");
    if (cl.has("--web") || cl.has("--web-bind")) throw UsageError("--web shows a live walk; --simulate-walk runs offline");
    const navigation::Route& route = *req.route;
    auto link = std::make_shared<navigation::NavigationLink>();
    link->logEnabled = true;   // the announcer reads it too
    WalkLog log(route, nullptr, req.logPath, false);
    std::string tactile = "t,m1,m2,m3,m4,m5,m6,m7,m8,m9\n";
    navigation::WalkOptions o;
    o.maxSeconds = req.seconds > 0.0 ? req.seconds : 3 * 3600.0;
    o.observe = [&](double t, const navigation::WalkerView&, const core::MotorLevels& levels, const navigation::NavigationStatus&) {
        log.drain(*link);
        if (!req.tactilePath.empty()) tactile += tactileRow(t, levels);
    };
    if (cl.has("--profile") || cl.has("--calibration") || cl.has("--arm"))
        std::cerr << "armadillo navigate: --simulate-walk uses the walker's own right arm; --profile, --calibration and --arm are for a device\n";
    const navigation::WalkResult r = navigation::simulateWalk(route, req.options, w, o, link);
    log.drain(*link);
    log.write();
    if (!req.tactilePath.empty()) core::writeFileAtomically(req.tactilePath, tactile);
    std::cout << navigation::walkResultJson(r, route, w) << "\n" << std::flush;
    return core::kExitOk;
}

/// A live walk's session: the arm (a device, the simulated forearm, or the phone on --osc-in), the
/// walk's position source and the navigation scene, all built by the live session.
live::LiveConfig liveWalkConfig(const CommandLine& cl, const NavigateRequest& req)
{
    live::LiveConfig config;
    if (cl.has("--port")) {
        config.source = live::LiveConfig::Source::Port;
        config.port = cl.value("--port");
        if (config.port.empty()) throw UsageError("--port needs a device name");
        config.baud = static_cast<int>(cl.integer("--baud", 57600, 1200, 4000000));
    } else if (req.armFromOsc) {
        config.source = live::LiveConfig::Source::Osc;
        config.oscInPort = req.oscPort;
        if (cl.has("--mount")) {
            config.osc.mount = link::mountFromArgument(cl.value("--mount"));
            config.osc.mountGiven = true;
        }
    } else {
        config.source = live::LiveConfig::Source::Simulator;
        config.motionFile = cl.value("--motion");
    }
    config.engine.scene = "navigate";
    config.engine.sceneConfig.side = req.arm == "left" ? core::ArmSide::Left : core::ArmSide::Right;
    readProfileOption(cl, config.engine);
    if (cl.has("--calibration")) config.calibration = link::loadCalibration(cl.value("--calibration"));
    config.tactileOut = req.tactilePath;
    config.logOut = req.sessionLogPath;   // the same session log and OSC stream as play's
    config.oscOut = req.oscOut;
    if (cl.has("--tactors")) config.tactors = tactorConfig(cl, config.engine.motorCount);   // IoError / InputError before anything runs
    config.walk.route = req.route;
    config.walk.options = req.options;
    using Positions = navigation::NavigationRig::Source;
    config.walk.positions = req.gpsd ? Positions::Gpsd : req.armFromOsc ? Positions::ArmOsc : Positions::Osc;
    config.walk.where = req.gpsd ? cl.value("--gpsd") : std::to_string(req.oscPort);
    readWebOptions(cl, config);
    return config;
}

/// Until the route's end (and its last sensation), --seconds, an interrupt or a failed scene.
void walk(live::LiveSession& session, const NavigateRequest& req, WalkLog& log)
{
    navigation::NavigationRig& nav = *session.navigation();
    const auto start = std::chrono::steady_clock::now();
    double finishedAt = -1.0;
    bool shownDown = false;
    while (!interrupted()) {
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (req.seconds > 0.0 && elapsed >= req.seconds) break;
        log.drain(*nav.link());
        const navigation::NavigationStatus st = nav.status();
        if (st.finished && st.sensation == navigation::Sensation::None && finishedAt < 0.0) finishedAt = elapsed;
        if (finishedAt >= 0.0 && elapsed > finishedAt + 0.5) break;
        reportWebPage(session, "armadillo navigate: ");
        if (!nav.sourceConnected() && !shownDown) std::cerr << "armadillo navigate: " << nav.describeSource() << " went away (reconnecting)\n";
        shownDown = !nav.sourceConnected();
        if (session.engine().failed()) {
            std::cerr << "armadillo navigate: the scene failed and was stopped (motors off): " << session.engine().failure() << "\n";
            break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
}

int runLiveWalk(const CommandLine& cl, const NavigateRequest& req)
{
    live::LiveConfig config = liveWalkConfig(cl, req);
    const bool wantsVoice = cl.has("--speak") || cl.has("--speech") || cl.has("--brlapi") || cl.has("--braille-display");
    if (cl.has("--rate") && !wantsVoice) throw UsageError("--rate sets the speech rate: use it with --speak");
    std::unique_ptr<ReaderIo> voice;
    if (wantsVoice) voice = std::make_unique<ReaderIo>(cl, true);   // IoError when the backend asked for cannot be opened
    installInterruptHandlers();
    WalkLog log(*req.route, voice.get(), req.logPath, true);   // the log under its own name as the walk goes
    live::LiveSession session(config);   // the position source: IoError (exit 4) when gpsd cannot be reached or the port is taken
    navigation::NavigationRig& nav = *session.navigation();
    nav.link()->logEnabled = !req.logPath.empty();
    if (const std::string kept = log.keptAside(); !kept.empty()) std::cerr << "armadillo navigate: " << kept << "\n";
    for (const std::string& line : session.keptAside()) std::cerr << "armadillo navigate: " << line << "\n";
    session.start();
    for (const std::string& line : session.outputLines()) std::cerr << "armadillo navigate: " << line << "\n";
    std::cerr << "armadillo navigate: " << nav.describeSource() << "\n";
    announceWebPage(session, "armadillo navigate: ");
    walk(session, req, log);
    session.stop();
    log.drain(*nav.link());
    session.finish();
    log.write();
    std::string summary = live::summaryJson(session.summary());
    summary.insert(summary.size() - 1, nav.summaryJson());
    std::cout << summary << "\n" << std::flush;
    return session.engine().failed() ? int(core::kExitFailure) : int(core::kExitOk);
}

} // namespace

int runNavigate(const Arguments& args)
{
    return guarded("navigate", [&]() -> int {
        CommandLine cl(
            "navigate", "--route ROUTE.gpx (--gpsd HOST[:PORT] | --osc-in PORT | --simulate-walk) [--port NAME | --simulate] [options]",
            "Walk a route guided by the arm alone (docs/NAVIGATION.md): the §4.1 compass toward the next waypoint, an\n"
            "arrival sensation and the waypoint's name in Arm Braille within the arrival radius, and sensations for off\n"
            "route, fix lost and the route's end. The route's first point is the start; guidance goes to point 2 first.\n"
            "Positions come from gpsd (--gpsd), over OSC (--osc-in: /armadillo/position lat lon [accuracy_m] or\n"
            "ZIG SIM's gps), or from a simulated walker guided by the motors (--simulate-walk: the whole walk offline,\n"
            "as fast as it computes). Ends at the route's end, after --seconds, or on SIGINT/SIGTERM, with every\n"
            "motor off, and prints one JSON line.",
            navigateOptionSpecs());
        if (!cl.parse(args)) return core::kExitOk;
        const NavigateRequest request = readNavigateRequest(cl);
        return request.walk ? runSimulatedWalk(cl, request) : runLiveWalk(cl, request);
    });
}

} // namespace armadillo::cli
