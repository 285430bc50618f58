#include "Pd/Commands.h"
#include "Core/Errors.h"
#include "Link/Mount.h"
#include "Link/TouchProfile.h"
#include "Osc/OscDialects.h"
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace armadillo::pd {

namespace {

core::InputError problem(const std::string& what) { return core::InputError("", 0, "", what); }

std::string joined(const std::vector<std::string>& names)
{
    std::string all;
    for (const auto& n : names) all += (all.empty() ? "" : " ") + n;
    return all;
}

double number(const std::vector<Atom>& args, std::size_t i, const std::string& message)
{
    if (i >= args.size() || !std::holds_alternative<double>(args[i]))
        throw problem(message + " needs a number" + (i < args.size() ? ", not '" + atomText(args[i]) + "'" : ""));
    return std::get<double>(args[i]);
}

std::string text(const std::vector<Atom>& args, std::size_t i, const std::string& message, const std::string& what)
{
    if (i >= args.size()) throw problem(message + " needs " + what);
    return atomText(args[i]);
}

void atMost(const std::vector<Atom>& args, std::size_t n, const std::string& message)
{
    if (args.size() > n) throw problem(message + " takes at most " + std::to_string(n) + " argument" + (n == 1 ? "" : "s"));
}

const char* const kMessages = "simulate port osc format mount stop calibration profile arm scene motors param panic resume bang";

} // namespace

std::vector<std::string> pdSceneNames()
{
    std::vector<std::string> all = engine::sceneNames();
    for (const auto& n : engine::hostedSceneNames()) all.push_back(n);
    return all;
}

std::string atomText(const Atom& a)
{
    if (const auto* s = std::get_if<std::string>(&a)) return *s;
    char buf[64];
    std::snprintf(buf, sizeof buf, "%g", std::get<double>(a));
    return buf;
}

Commands::Commands(Instrument& instrument, std::string directory, std::shared_ptr<core::MotorTargets> targets)
    : instrument_(instrument), directory_(std::move(directory)), targets_(std::move(targets))
{
}

std::string Commands::resolve(const std::string& path) const
{
    if (path.empty() || path.front() == '/' || directory_.empty()) return path;
    return (std::filesystem::path(directory_) / path).lexically_normal().string();
}

bool Commands::handle(const std::string& selector, const std::vector<Atom>& args)
{
    // A setting that changes nothing running now (an OSC format without an OSC source): kept for later.
    const auto keep = [this](const Settings& s) {
        settings_ = s;
        return false;
    };
    Settings next = settings_;
    const bool sourceRuns = settings_.source != Settings::Source::None;
    if (selector == "bang") return true;
    if (selector == "simulate") {
        atMost(args, 1, "simulate");
        next.source = Settings::Source::Simulate;
        next.motionFile = args.empty() ? std::string() : resolve(atomText(args[0]));
        if (!next.motionFile.empty() && !std::filesystem::is_regular_file(next.motionFile))
            throw problem("simulate: no motion file '" + next.motionFile + "'");
    } else if (selector == "port") {
        atMost(args, 2, "port");
        next.source = Settings::Source::Port;
        next.port = text(args, 0, "port", "a device name (port /dev/ttyUSB0 [BAUD])");
        next.baud = args.size() > 1 ? static_cast<int>(number(args, 1, "port's baud rate")) : 57600;
        if (next.baud < 300 || next.baud > 4000000) throw problem("port: baud rate " + std::to_string(next.baud) + " out of range");
    } else if (selector == "osc") {
        atMost(args, 1, "osc");
        const double p = number(args, 0, "osc (the UDP port)");
        if (!(p >= 1 && p <= 65535) || p != std::floor(p)) throw problem("osc: port " + atomText(args[0]) + " is not 1-65535");
        next.source = Settings::Source::Osc;
        next.oscPort = static_cast<int>(p);
    } else if (selector == "format") {
        atMost(args, 1, "format");
        next.format = text(args, 0, "format", "a sender's format (" + osc::oscFormatNames() + ")");
        osc::OscFormat f {};
        if (!osc::parseOscFormat(next.format, f)) throw problem("format: unknown format '" + next.format + "' (one of " + osc::oscFormatNames() + ")");
        if (next.source != Settings::Source::Osc) return keep(next);
    } else if (selector == "mount") {
        atMost(args, 1, "mount");
        const std::string m = text(args, 0, "mount", "a preset name or a mount file");
        try {
            (void) link::mountFromArgument(m);
            next.mount = m;
        } catch (const core::InputError&) {
            next.mount = resolve(m);
            (void) link::mountFromArgument(next.mount);   // still bad: its own error names it
        }
        if (next.source != Settings::Source::Osc) return keep(next);
    } else if (selector == "stop") {
        settings_.source = Settings::Source::None;
        instrument_.stopSource();
        return false;
    } else if (selector == "calibration") {
        atMost(args, 1, "calibration");
        next.calibrationFile = resolve(text(args, 0, "calibration", "a calibration file"));
        (void) link::loadCalibration(next.calibrationFile);   // a bad file is refused here, naming it
        if (!sourceRuns) return keep(next);
    } else if (selector == "profile") {
        atMost(args, 1, "profile");
        next.profileFile = resolve(text(args, 0, "profile", "a touch profile file"));
        (void) link::loadTouchProfile(next.profileFile);
    } else if (selector == "arm") {
        atMost(args, 1, "arm");
        const std::string side = text(args, 0, "arm", "left or right");
        if (side != "left" && side != "right") throw problem("arm must be left or right, not '" + side + "'");
        next.side = side == "left" ? core::ArmSide::Left : core::ArmSide::Right;
    } else if (selector == "scene") {
        setScene(args);
        return false;
    } else if (selector == "param") {
        setParam(args);
        return false;
    } else if (selector == "motors") {
        setMotors(args);
        return false;
    } else if (selector == "panic") {
        instrument_.panic();
        return false;
    } else if (selector == "resume") {
        instrument_.resume();
        return false;
    } else {
        throw problem("unknown message '" + selector + "' (messages: " + kMessages + ")");
    }
    applyOrRestore(next);
    return false;
}

void Commands::applyOrRestore(const Settings& next)
{
    const Settings before = settings_;
    settings_ = next;
    try {
        instrument_.apply(settings_);
    } catch (...) {
        settings_ = before;
        try {
            instrument_.apply(settings_);   // what ran before runs again
        } catch (...) {
            settings_.source = Settings::Source::None;
            instrument_.stopSource();
        }
        throw;
    }
}

void Commands::setScene(const std::vector<Atom>& args)
{
    const std::string name = text(args, 0, "scene", "a scene name (" + joined(pdSceneNames()) + ")");
    const auto all = pdSceneNames();
    if (std::find(all.begin(), all.end(), name) == all.end())
        throw problem("unknown scene '" + name + "' (scenes: " + joined(all) + ")");
    Settings next = settings_;
    next.scene = name;
    next.params.clear();   // the parameters were the previous scene's
    next.sceneText.clear();
    for (std::size_t i = 1; i < args.size(); ++i) next.sceneText += (i > 1 ? " " : "") + atomText(args[i]);
    if (name == "braille" && next.sceneText.empty()) next.sceneText = "armadillo";
    if (name == "score") next.sceneText = next.sceneText.empty() ? std::string("rite-of-spring") : next.sceneText;
    if (name == "score" && std::filesystem::path(next.sceneText).has_extension()) next.sceneText = resolve(next.sceneText);
    applyOrRestore(next);
}

void Commands::setParam(const std::vector<Atom>& args)
{
    if (args.size() != 2) throw problem("param takes a parameter ID and a value (param theremin.range 24)");
    const std::string id = atomText(args[0]), value = atomText(args[1]);
    if (const std::string why = engine::sceneParameterProblem(settings_.scene, id + "=" + value); !why.empty())
        throw problem("param " + id + ": " + why);
    instrument_.setParameter(id, value);
    auto it = std::find_if(settings_.params.begin(), settings_.params.end(), [&](const auto& p) { return p.first == id; });
    if (it == settings_.params.end()) settings_.params.emplace_back(id, value);
    else it->second = value;
}

void Commands::setMotors(const std::vector<Atom>& args)
{
    if (args.size() != static_cast<std::size_t>(core::MotorTargets::kCount))
        throw problem("motors takes " + std::to_string(core::MotorTargets::kCount) + " levels 0-15 (motor 1 first), not " +
                      std::to_string(args.size()));
    core::MotorTargets::Levels levels {};
    for (std::size_t i = 0; i < args.size(); ++i) {
        const double v = number(args, i, "motors (level " + std::to_string(i + 1) + ")");
        if (!(v >= 0.0 && v <= static_cast<double>(core::MotorTargets::kMaxLevel)))
            throw problem("motors: level " + std::to_string(i + 1) + " is " + atomText(args[i]) + ", not 0-15");
        levels[i] = static_cast<float>(v);
    }
    targets_->set(levels);
    if (settings_.scene != "patch")
        throw problem("motors: kept, but the scene is '" + settings_.scene + "'; they drive the grid in scene patch");
}

engine::EngineConfig Commands::engineConfig(double sampleRate) const
{
    engine::EngineConfig config;
    config.scene = settings_.scene;
    config.sceneConfig.sampleRate = sampleRate;
    config.sceneConfig.side = settings_.side;
    config.sceneConfig.motorTargets = targets_;
    if (settings_.scene == "braille") config.sceneConfig.text = settings_.sceneText;
    if (settings_.scene == "score") config.sceneConfig.score = settings_.sceneText;
    for (const auto& [id, value] : settings_.params) config.parameters.push_back(id + "=" + value);
    if (!settings_.profileFile.empty()) config.motorGain = link::touchProfileGains(link::loadTouchProfile(settings_.profileFile));
    return config;
}

link::Calibration Commands::calibration() const
{
    return settings_.calibrationFile.empty() ? link::defaultCalibration() : link::loadCalibration(settings_.calibrationFile);
}

} // namespace armadillo::pd
